!> A whole run: output folder, time loop, outputs, energy history, progress and summary.
module mpm_run
    use, intrinsic :: iso_fortran_env, only: output_unit
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_input, exit_other
    use mpm_clock, only: wall_time
    use mpm_system, only: peak_memory_mb
    use mpm_particles, only: particle_bytes
    use mpm_case, only: case_type
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        compute_energies, has_text, nphases, phase_names, phase_other, phase_output
    use mpm_stencil, only: stencil_bytes
    use mpm_grid, only: grid_bytes
    use mpm_output, only: output_writer_type, new_output_writer, write_output, remove_outputs
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
        real(wp) :: t_start, t_last_progress, dt, next_output, next_history, eps_t, clock
        character(len=256) :: msg
        logical :: written

        call new_simulation(sim, case, error)
        if (allocated(error)) return
        summary%particles = sim%particles%n
        summary%nodes = sim%grid%nnodes
        if (sim%particles%n == 0) then
            call fatal_error(error, case%file//": the case holds no particles", exit_input)
            return
        end if

        history_unit = -1
        if (options%write_files) then
            call prepare_output_dir(case, error)
            if (allocated(error)) return
            call new_output_writer(writer, case, case%output_dir, error)
            if (allocated(error)) return
            open (newunit=history_unit, file=case%output_dir//"/history.csv", status="replace", &
                action="write", iostat=stat, iomsg=msg)
            if (stat /= 0) then
                call fatal_error(error, case%output_dir//"/history.csv: "//trim(msg), exit_other)
                return
            end if
            write (history_unit, "(a)") "time,step,kinetic_energy,strain_energy," &
                //"potential_energy,damping_work,total"
            call write_output(writer, int(sim%step), sim%time, sim%particles, sim%grid, error)
            if (allocated(error)) return
            summary%outputs = 1
            call write_history(history_unit, sim)
        end if
        if (.not. options%quiet) then
            write (output_unit, "(a,i0,a,i0,a)") "mpm_geo: case '"//case%name//"', ", &
                sim%particles%n, " particles, ", sim%grid%nnodes, " nodes"
        end if

        eps_t = 1.0e-12_wp*case%tend
        next_output = huge(1.0_wp)
        if (case%output_interval > 0.0_wp) next_output = case%output_interval
        next_history = 0.0_wp
        t_start = wall_time()
        t_last_progress = t_start
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
                    call write_output(writer, int(sim%step), sim%time, sim%particles, &
                        sim%grid, error)
                    if (allocated(error)) exit
                    summary%outputs = summary%outputs + 1
                    do while (next_output <= sim%time + eps_t)
                        next_output = next_output + case%output_interval
                    end do
                    written = .true.
                end if
                if (sim%time >= next_history - eps_t .or. written) then
                    call compute_energies(sim)
                    call write_history(history_unit, sim)
                    next_history = sim%time + case%history_interval
                end if
                sim%phase_time(phase_output) = sim%phase_time(phase_output) &
                    + (wall_time() - clock)
            end if
            if (.not. options%quiet .and. wall_time() - t_last_progress >= case%progress_seconds) then
                t_last_progress = wall_time()
                call print_progress(sim, case%tend, t_last_progress - t_start)
            end if
        end do
        summary%steps = sim%step
        summary%time = sim%time
        summary%wall = wall_time() - t_start
        summary%phase_time = sim%phase_time
        if (summary%wall > 0.0_wp) summary%particle_steps_per_second = &
            real(sim%particles%n, wp)*real(sim%step, wp)/summary%wall
        if (history_unit >= 0) close (history_unit)
        if (allocated(error)) then
            if (options%write_files) error%message = error%message//new_line("a")// &
                "outputs written so far are in "//case%output_dir
            return
        end if

        if (has_text(case%save_state)) then
            call save_state(case%save_state, case, sim%particles, sim%time, int(sim%step), error)
            if (allocated(error)) return
        end if
        ! particle arrays and the per-step scratch: stencils, order, cell
        summary%bytes_per_particle = particle_bytes(sim%particles) + stencil_bytes(sim%stencils)
        summary%bytes_per_node = grid_bytes(sim%grid)
        summary%peak_memory_mb = peak_memory_mb()
        if (.not. options%quiet) call print_summary(summary, case)
    end subroutine run_case

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

    subroutine print_progress(sim, tend, elapsed)
        type(simulation_type), intent(in) :: sim
        real(wp), intent(in) :: tend, elapsed

        real(wp) :: rate, eta

        rate = real(sim%step, wp)/max(elapsed, 1.0e-9_wp)
        eta = elapsed*(tend - sim%time)/max(sim%time, tiny(1.0_wp))
        write (output_unit, "(a,i9,a,es11.4,a,es9.2,a,es10.3,a,f10.1,a,a)") "step", sim%step, &
            "  t =", sim%time, " s  dt =", sim%dt, " s  KE =", sim%energy%kinetic, " J ", &
            rate, " steps/s  ETA ", trim(format_seconds(eta))
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
