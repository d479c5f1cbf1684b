!> A whole run: output folder, time loop, outputs, energy history, progress and summary.
module mpm_run
    use, intrinsic :: iso_fortran_env, only: output_unit
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_input, exit_other
    use mpm_clock, only: wall_time
    use mpm_system, only: peak_memory_mb
    use mpm_strings, only: int_text
    use mpm_particles, only: particles_type, particle_bytes, pack_particles, rebuild_particles, &
        record_length
    use mpm_case, only: case_type
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        compute_energies, has_text, nphases, phase_names, phase_other, phase_output, agree
    use mpm_parallel, only: image_id, image_count, counts_of_images, gather_on_first
    use mpm_decomposition, only: image_grids
    use mpm_stencil, only: stencil_bytes
    use mpm_grid, only: grid_bytes
    use mpm_output, only: output_writer_type, new_output_writer, write_output, write_index, &
        remove_outputs, write_terrain
    use mpm_state, only: save_state
    use mpm_filesystem, only: make_directory, directory_exists
    implicit none
    private
    public :: run_options_type, run_summary_type, run_case

    !> How a run is driven.
    type :: run_options_type
        logical :: quiet = .false.
            !! no progress lines and no summary on standard output
        logical :: write_files = .true.
            !! write the output folder (HDF5, XDMF, history); tests may turn it off
    end type run_options_type

    !> Figures of a finished run.
    type :: run_summary_type
        integer :: particles = 0
            !! number of particles
        integer :: nodes = 0
            !! number of grid nodes
        integer(i8) :: steps = 0
            !! steps done
        real(wp) :: time = 0.0_wp
            !! simulated time reached [s]
        real(wp) :: wall = 0.0_wp
            !! wall-clock time of the time loop [s]
        real(wp) :: particle_steps_per_second = 0.0_wp
            !! particles x steps / wall time [1/s]
        integer :: outputs = 0
            !! particle output files written
        integer :: bytes_per_particle = 0
            !! particle storage per particle [bytes]
        integer :: bytes_per_node = 0
            !! grid storage per node [bytes]
        real(wp) :: peak_memory_mb = 0.0_wp
            !! peak resident memory of the process [MB]
        real(wp) :: phase_time(nphases) = 0.0_wp
            !! wall time per phase of the time loop (mpm_solver phase_names) [s]
    end type run_summary_type

contains

    !> Run a case from t = 0 to tend, writing its outputs; `sim` holds the final state.
    subroutine run_case(case, options, sim, summary, error)
        type(case_type), intent(in) :: case
            !! resolved case
        type(run_options_type), intent(in) :: options
            !! how to run
        type(simulation_type), intent(out) :: sim
            !! the simulation, at tend on return
        type(run_summary_type), intent(out) :: summary
            !! figures of the run
        type(error_type), allocatable, intent(out) :: error
            !! set on any failure

        type(output_writer_type) :: writer
        integer :: history_unit, stat
        integer(i8) :: total
        logical :: lead, quiet
        real(wp) :: imbalance
        integer, parameter :: imbalance_steps = 50
        real(wp) :: t_start, t_last_progress, dt, next_output, next_history, eps_t, clock
        character(len=256) :: msg
        logical :: written

        call new_simulation(sim, case, error)
        call agree(error)
        if (allocated(error)) return
        ! on several images: image 1 prints, writes the history and the index; every image
        ! writes its part of the particle output
        lead = image_id() == 1
        quiet = options%quiet .or. .not. lead
        total = sum(counts_of_images(sim%particles%n))
        summary%particles = int(total)
        summary%nodes = product(case%ncells(1:case%dim) + 1)
        if (total == 0) then
            call fatal_error(error, case%file//": the case holds no particles", exit_input)
            if (.not. lead) error%message = ""
            return
        end if

        history_unit = -1
        if (options%write_files) then
            if (lead) call prepare_output_dir(case, error)
            call agree(error)
            if (allocated(error)) return
            call new_output_writer(writer, case, case%output_dir, error, image_id(), image_count())
            if (.not. allocated(error) .and. lead) then
                open (newunit=history_unit, file=case%output_dir//"/history.csv", &
                    status="replace", action="write", iostat=stat, iomsg=msg)
                if (stat /= 0) then
                    call fatal_error(error, case%output_dir//"/history.csv: "//trim(msg), &
                        exit_other)
                else
                    write (history_unit, "(a)") "time,step,kinetic_energy,strain_energy," &
                        //"potential_energy,damping_work,total"
                end if
            end if
            ! the terrain surface, to open in ParaView beside the particles
            if (lead .and. allocated(sim%grid%terrain)) call write_terrain(case%output_dir, &
                sim%grid%terrain%corner, error)
            call agree(error)
            if (allocated(error)) return
            call write_part(writer, sim, error)
            if (allocated(error)) return
            summary%outputs = 1
            if (lead) call write_history(history_unit, sim)
        end if
        if (.not. quiet) then
            write (output_unit, "(a,i0,a,i0,a)") "mpm_geo: case '"//case%name//"', ", &
                total, " particles, ", summary%nodes, " nodes"
            if (image_count() > 1) write (output_unit, "(a,i0,a,a,a)") "mpm_geo: ", &
                image_count(), " images, slabs across ", axis_name(sim%dec%axis), &
                ", cuts at cells "//cuts_text(sim%dec%cuts)
        end if

        eps_t = 1.0e-12_wp*case%tend
        next_output = huge(1.0_wp)
        if (case%output_interval > 0.0_wp) next_output = case%output_interval
        next_history = 0.0_wp
        t_start = wall_time()
        t_last_progress = t_start
        imbalance = 0.0_wp
        do while (sim%time < case%tend - eps_t)
            clock = wall_time()
            dt = min(stable_time_step(sim), case%tend - sim%time)
            sim%phase_time(phase_other) = sim%phase_time(phase_other) + (wall_time() - clock)
            call advance(sim, dt, error)
            if (allocated(error)) exit
            written = .false.
            clock = wall_time()
            if (options%write_files) then
                if (sim%time >= next_output - eps_t .or. sim%time >= case%tend - eps_t) then
                    call compute_energies(sim)
                    call write_part(writer, sim, error)
                    if (allocated(error)) exit
                    summary%outputs = summary%outputs + 1
                    do while (next_output <= sim%time + eps_t)
                        next_output = next_output + case%output_interval
                    end do
                    written = .true.
                end if
                if (sim%time >= next_history - eps_t .or. written) then
                    call compute_energies(sim)
                    if (lead) call write_history(history_unit, sim)
                    next_history = sim%time + case%history_interval
                end if
                sim%phase_time(phase_output) = sim%phase_time(phase_output) &
                    + (wall_time() - clock)
            end if
            ! the particle counts of the images, now and then (collective: by step number)
            if (image_count() > 1 .and. mod(sim%step, int(imbalance_steps, i8)) == 0) then
                imbalance = load_imbalance(sim%particles%n)
            end if
            if (.not. quiet .and. wall_time() - t_last_progress >= case%progress_seconds) then
                t_last_progress = wall_time()
                call print_progress(sim, case%tend, t_last_progress - t_start, imbalance)
            end if
        end do
        summary%steps = sim%step
        summary%time = sim%time
        summary%wall = wall_time() - t_start
        summary%phase_time = sim%phase_time
        if (summary%wall > 0.0_wp) summary%particle_steps_per_second = &
            real(total, wp)*real(sim%step, wp)/summary%wall
        if (history_unit >= 0) close (history_unit)
        if (allocated(error)) then
            ! (an image that does not report the failure has no message)
            if (options%write_files .and. len(error%message) > 0) error%message = &
                error%message//new_line("a")//"outputs written so far are in "//case%output_dir
            return
        end if

        if (has_text(case%save_state)) then
            call save_run_state(sim, error)
            if (allocated(error)) return
        end if
        ! particle arrays and the per-step scratch: stencils, order, cell
        summary%bytes_per_particle = particle_bytes(sim%particles) + stencil_bytes(sim%stencils)
        summary%bytes_per_node = grid_bytes(sim%grid)
        summary%peak_memory_mb = peak_memory_mb()
        if (.not. quiet) call print_summary(summary, case)
    end subroutine run_case

    !> Write this image's part of an output (collective: image 1 writes the index).
    subroutine write_part(writer, sim, error)
        type(output_writer_type), intent(inout) :: writer
            !! the run's writer
        type(simulation_type), intent(in) :: sim
            !! the simulation
        type(error_type), allocatable, intent(out) :: error
            !! set (on every image) when an image cannot write

        integer(i8), allocatable :: counts(:)
        real(wp), allocatable :: origins(:, :)
        integer, allocatable :: nns(:, :)

        if (image_count() == 1) then
            call write_output(writer, int(sim%step), sim%time, sim%particles, sim%grid, error)
        else
            counts = counts_of_images(sim%particles%n)
            call image_grids(sim%case, sim%dec, origins, nns)
            call write_output(writer, int(sim%step), sim%time, sim%particles, sim%grid, error, &
                counts, origins, nns, defer_index=.true.)
            ! every part is complete before the index names it
            call agree(error)
            if (.not. allocated(error)) call write_index(writer, error)
        end if
        call agree(error)
    end subroutine write_part

    !> The state file of the run (collective): on several images, image 1 collects every
    !> particle, in the order of the ids (the order of one image), and writes the file.
    subroutine save_run_state(sim, error)
        type(simulation_type), intent(in) :: sim
            !! the simulation
        type(error_type), allocatable, intent(out) :: error
            !! set (on every image) when the state cannot be written

        type(particles_type) :: all
        real(wp), allocatable :: mine(:), records(:), ordered(:)
        integer :: r, q, k, n

        if (image_count() == 1) then
            call save_state(sim%case%save_state, sim%case, sim%particles, sim%time, &
                int(sim%step), error)
            return
        end if
        call pack_particles(sim%particles, [(.true., q = 1, sim%particles%n)], mine)
        call gather_on_first(mine, records)
        if (image_id() == 1) then
            ! records in id order (the id is the last value of a record)
            r = record_length(sim%particles)
            n = size(records)/r
            allocate (ordered(size(records)))
            do q = 1, n
                k = nint(records(q*r))
                ordered((k - 1)*r + 1:k*r) = records((q - 1)*r + 1:q*r)
            end do
            all = sim%particles
            call rebuild_particles(all, [(.false., q = 1, all%n)], ordered, error)
            if (.not. allocated(error)) then
                deallocate (all%id)
                call save_state(sim%case%save_state, sim%case, all, sim%time, int(sim%step), &
                    error)
            end if
        end if
        call agree(error)
    end subroutine save_run_state

    !> Largest particle count of an image over the mean count (collective).
    real(wp) function load_imbalance(n)
        integer, intent(in) :: n
            !! this image's particles

        integer(i8), allocatable :: counts(:)

        counts = counts_of_images(n)
        load_imbalance = real(maxval(counts), wp)*real(size(counts), wp) &
            /max(1.0_wp, real(sum(counts), wp))
    end function load_imbalance

    pure function axis_name(axis) result(name)
        integer, intent(in) :: axis
        character(len=1) :: name
        name = "-"
        if (axis >= 1 .and. axis <= 3) name = "xyz"(axis:axis)
    end function axis_name

    function cuts_text(cuts) result(text)
        integer, intent(in) :: cuts(:)
        character(len=:), allocatable :: text

        integer :: k

        text = ""
        do k = 2, size(cuts) - 1
            text = text//int_text(cuts(k))
            if (k < size(cuts) - 1) text = text//", "
        end do
    end function cuts_text

    !> Create the output folder; refuse an existing one unless overwriting was asked for.
    subroutine prepare_output_dir(case, error)
        type(case_type), intent(in) :: case
        type(error_type), allocatable, intent(out) :: error

        if (directory_exists(case%output_dir) .and. .not. case%overwrite) then
            call fatal_error(error, "output folder '"//case%output_dir//"' exists already; "// &
                "mpm_geo does not overwrite results: pass --overwrite (or set "// &
                """output"": {""overwrite"": true}), or choose another folder with --output DIR", &
                exit_input)
            return
        end if
        call make_directory(case%output_dir, error)
        if (allocated(error)) return
        call remove_outputs(case%output_dir, case%name, error)
    end subroutine prepare_output_dir

    subroutine write_history(unit, sim)
        integer, intent(in) :: unit
        type(simulation_type), intent(in) :: sim

        associate (e => sim%energy)
            write (unit, "(es23.15e3,',',i0,5(',',es23.15e3))") sim%time, sim%step, e%kinetic, &
                e%strain, e%potential, e%damping, e%kinetic + e%strain + e%potential + e%damping
        end associate
    end subroutine write_history

    subroutine print_progress(sim, tend, elapsed, imbalance)
        type(simulation_type), intent(in) :: sim
        real(wp), intent(in) :: tend, elapsed
        real(wp), intent(in) :: imbalance
            !! largest particle count of an image over the mean (0: one image)

        real(wp) :: rate, eta

        rate = real(sim%step, wp)/max(elapsed, 1.0e-9_wp)
        eta = elapsed*(tend - sim%time)/max(sim%time, tiny(1.0_wp))
        write (output_unit, "(a,i9,a,es11.4,a,es9.2,a,es10.3,a,f10.1,a,a,a)") "step", sim%step, &
            "  t =", sim%time, " s  dt =", sim%dt, " s  KE =", sim%energy%kinetic, " J ", &
            rate, " steps/s  ETA ", trim(format_seconds(eta)), trim(imbalance_text(imbalance))
        flush (output_unit)
    end subroutine print_progress

    subroutine print_summary(summary, case)
        type(run_summary_type), intent(in) :: summary
        type(case_type), intent(in) :: case

        integer :: k

        write (output_unit, "(a)") "mpm_geo: finished case '"//case%name//"'"
        write (output_unit, "(a,i0)") "  particles            ", summary%particles
        write (output_unit, "(a,i0)") "  nodes                ", summary%nodes
        write (output_unit, "(a,i0)") "  steps                ", summary%steps
        write (output_unit, "(a,es12.5,a)") "  simulated time       ", summary%time, " s"
        write (output_unit, "(a,f12.3,a)") "  wall time            ", summary%wall, " s"
        write (output_unit, "(a,es12.4)") "  particle-steps/s     ", summary%particle_steps_per_second
        write (output_unit, "(a,f10.1,a)") "  peak memory          ", summary%peak_memory_mb, " MB"
        write (output_unit, "(a,i0,a)") "  particle storage     ", summary%bytes_per_particle, &
            " bytes/particle"
        write (output_unit, "(a,i0,a)") "  grid storage         ", summary%bytes_per_node, &
            " bytes/node"
        write (output_unit, "(a,i0,a)") "  output files         ", summary%outputs, &
            " in "//case%output_dir
        write (output_unit, "(a)", advance="no") "  time per phase      "
        do k = 1, nphases
            write (output_unit, "(1x,a,'=',f0.3)", advance="no") trim(phase_names(k)), &
                summary%phase_time(k)
        end do
        write (output_unit, "(a)") " s"
    end subroutine print_summary

    function imbalance_text(imbalance) result(text)
        real(wp), intent(in) :: imbalance
        character(len=:), allocatable :: text

        character(len=32) :: buf

        text = ""
        if (imbalance <= 0.0_wp) return
        write (buf, "(a,f0.2)") "  imbalance ", imbalance
        text = trim(buf)
    end function imbalance_text

    function format_seconds(s) result(text)
        real(wp), intent(in) :: s
        character(len=:), allocatable :: text

        character(len=32) :: buf

        if (s < 120.0_wp) then
            write (buf, "(i0,a)") nint(s), " s"
        else if (s < 7200.0_wp) then
            write (buf, "(f0.1,a)") s/60.0_wp, " min"
        else
            write (buf, "(f0.1,a)") s/3600.0_wp, " h"
        end if
        text = trim(adjustl(buf))
    end function format_seconds

end module mpm_run
