!> A whole run: output folder, time loop, outputs, energy history, progress and summary.
module mpm_run
    use, intrinsic :: iso_fortran_env, only: output_unit
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_input, exit_other, exit_numerical, &
        exit_interrupted
    use mpm_clock, only: wall_time
    use mpm_system, only: peak_memory_mb
    use mpm_strings, only: int_text
    use mpm_signals, only: catch_stop_signals, release_stop_signals, stop_signal, signal_name
    use mpm_particles, only: particles_type, particle_bytes, pack_particles, rebuild_particles, &
        record_length
    use mpm_case, only: case_type, initial_k0
    use mpm_history, only: open_history, write_history
    use mpm_motion, only: half_cell_notes
    use mpm_case_guard, only: snapshot_in_file
    use mpm_setup, only: start_simulation
    use mpm_solver, only: simulation_type, advance, stable_time_step, &
        compute_energies, has_text, nphases, phase_names, phase_other, phase_output, agree, &
        contact_loads, resume_simulation, energy_record
    use mpm_parallel, only: image_id, image_count, counts_of_images, gather_on_first, &
        max_over_images
    use mpm_decomposition, only: image_grids
    use mpm_stencil, only: stencil_bytes
    use mpm_grid, only: grid_bytes
    use mpm_output, only: output_writer_type, new_output_writer, write_output, write_index, &
        remove_outputs, write_terrain, output_list, resume_output_writer, output_count
    use mpm_state, only: save_state, run_record_type
    use mpm_filesystem, only: make_directory, directory_exists, file_exists, rename_file, &
        remove_file, folder_lock_type, lock_folder, text_file_type, open_text_file, put_line, &
        flush_text_file, close_text_file
    use mpm_memory_check, only: check_memory
    use mpm_threads, only: thread_governor_type, new_thread_governor, governor_threads, &
        governor_step, governor_text, set_threads
    implicit none
    private
    public :: run_options_type, run_summary_type, run_case, checkpoint_path

    integer, parameter :: request_due = 1
        !! set by checkpoint_request when a checkpoint is due (a stop signal adds its number)

    !> A copy of the state after a healthy step, kept by the blow-up guard: in a file of the
    !> output folder (guard_copy_path, the default) or in memory.
    type :: snapshot_type
        logical :: taken = .false.
            !! a copy was taken
        logical :: in_file = .true.
            !! the copy is the file guard_copy_path (else `particles` and `run`)
        type(particles_type) :: particles
            !! this image's particles (a copy in memory)
        real(wp) :: time = 0.0_wp
            !! simulated time [s]
        integer(i8) :: step = 0
            !! steps done
        type(run_record_type) :: run
            !! how the run went on from there
    end type snapshot_type

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
        character(len=:), allocatable :: threads
            !! the OpenMP threads the steps used (mpm_threads::governor_text)
        real(wp) :: peak_kinetic = 0.0_wp
            !! largest kinetic energy at the history times [J]
        real(wp) :: final_kinetic = 0.0_wp
            !! kinetic energy at the end [J]
    end type run_summary_type

contains

    !> Run a case from t = 0 (or from a checkpoint) to tend, writing its outputs; `sim` holds
    !> the final state.
    !>
    !> Checkpoints (case key checkpoint, or the command line) are written every N steps and
    !> every T minutes of wall time, and when SIGTERM or SIGINT arrives; after a signal the run
    !> stops with exit_interrupted. `restart` continues from a checkpoint: the particles, the
    !> clock, the energies, the contact loads and the output schedule are those of the
    !> checkpoint, the outputs continue in its folder, and on one image the rest of the run is
    !> the same, bit for bit, as one that was never stopped. The blow-up guard keeps a copy
    !> of the state every guard.snapshot_steps steps, as a checkpoint in the output folder
    !> (.last_healthy.h5, removed when the run ends) or in memory (guard.snapshot_in), and
    !> leaves it as last_healthy.h5 when it stops the run.
    subroutine run_case(case, options, sim, summary, error, restart, run)
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
        character(len=*), intent(in), optional :: restart
            !! checkpoint to continue from (with `run`)
        type(run_record_type), intent(in), optional :: run
            !! the run record of that checkpoint (read_run_record)

        type(output_writer_type) :: writer
        type(snapshot_type) :: snapshot
        type(folder_lock_type) :: lock
            !! image 1's lock on the output folder, released when run_case returns
        type(text_file_type) :: history_unit
        type(error_type), allocatable :: ignored
        integer :: request
        logical :: history_open
        integer(i8) :: total, first_step
        logical :: lead, quiet, resumed
        real(wp) :: imbalance
        integer, parameter :: imbalance_steps = 50
        real(wp) :: t_start, t_last_progress, dt, next_output, next_history, eps_t, clock
        real(wp) :: wall_before, t_last_checkpoint, first_time, step_start
        logical :: written, copies
        type(thread_governor_type) :: threads
        integer :: nthreads
        integer, parameter :: equilibrium_steps = 100
            !! steps over which a geostatic start is checked for rest
        logical :: check_rest
        logical, allocatable :: noted(:)
        real(wp) :: start_kinetic

        resumed = present(restart) .and. present(run)
        call check_memory(case, error, restart)
        call agree(error)
        if (allocated(error)) return
        if (resumed) then
            call start_simulation(sim, case, error, restart)
            if (.not. allocated(error)) call resume_simulation(sim, run, error)
            if (allocated(error)) error%message = "cannot restart from '"//restart//"': "// &
                error%message
        else
            call start_simulation(sim, case, error)
        end if
        call agree(error)
        if (allocated(error)) return
        ! on several images: image 1 prints, writes the history and the index; every image
        ! writes its part of the particle output
        lead = image_id() == 1
        quiet = options%quiet .or. .not. lead
        total = sum(counts_of_images(sim%particles%n))
        summary%particles = int(total)
        summary%nodes = product(case%domain%ncells(1:case%dim) + 1)
        if (total == 0) then
            call fatal_error(error, case%file//": the case holds no particles", exit_input)
            if (.not. lead) error%message = ""
            return
        end if

        eps_t = 1.0e-12_wp*case%time%tend
        next_output = huge(1.0_wp)
        if (case%output%interval > 0.0_wp) next_output = case%output%interval
        next_history = 0.0_wp
        wall_before = 0.0_wp
        if (resumed) then
            next_output = run%next_output
            next_history = run%next_history
            wall_before = run%wall
        end if
        history_open = .false.
        if (options%write_files) then
            if (lead .and. resumed) call resume_output_dir(case, sim%step, lock, error)
            if (lead .and. .not. resumed) call prepare_output_dir(case, lock, error)
            call agree(error)
            if (allocated(error)) return
            call new_output_writer(writer, case, case%output%directory, error, image_id(), image_count())
            if (.not. allocated(error) .and. resumed) call resume_output_writer(writer, &
                run%output_time, run%output_step, run%output_counts, run%output_id, error)
            if (.not. allocated(error) .and. lead) then
                call open_history(case, resumed, history_unit, error)
                history_open = .not. allocated(error)
            end if
            ! the terrain surface, to open in ParaView beside the particles
            if (lead .and. allocated(sim%grid%terrain) .and. .not. allocated(error)) then
                call write_terrain(case%output%directory, sim%grid%terrain%corner, error)
            end if
            call agree(error)
            if (allocated(error)) return
            if (.not. resumed) then
                call write_part(writer, sim, error)
                if (allocated(error)) return
                if (lead) call write_history(history_unit, sim)
            end if
            summary%outputs = output_count(writer)
        end if
        if (.not. quiet) then
            if (resumed) then
                write (output_unit, "(a,i0,a,es12.5,a)") "mpm_geo: restart from '"// &
                    restart//"' at step ", sim%step, ", t = ", sim%time, " s"
            end if
            write (output_unit, "(a,i0,a,i0,a)") "mpm_geo: case '"//case%name//"', ", &
                total, " particles, ", summary%nodes, " nodes"
            if (image_count() > 1) write (output_unit, "(a,i0,a,a,a)") "mpm_geo: ", &
                image_count(), " images, slabs across ", axis_name(sim%dec%axis), &
                ", cuts at cells "//cuts_text(sim%dec%cuts)
        end if

        first_step = sim%step
        first_time = sim%time
        t_start = wall_time()
        t_last_progress = t_start
        t_last_checkpoint = t_start
        imbalance = 0.0_wp
        if (case%checkpoint%on_signal) call catch_stop_signals()
        ! the guard's copy is only written beside the outputs: no files, no copy
        copies = case%guard%snapshot_steps > 0 .and. options%write_files
        snapshot%in_file = case%guard%snapshot_in == snapshot_in_file
        ! (a copy that cannot be written skips the loop: the failure is reported below)
        if (copies) call take_snapshot(snapshot, sim, writer, next_output, next_history, &
            wall_before, error)
        ! the thread count of each step: the fastest (mpm_threads), starting with the largest
        call new_thread_governor(threads)
        nthreads = threads%most
        ! a geostatic start (initial_stress.type = "k0"): whether the ground is at rest
        check_rest = case%initial_stress%type == initial_k0 .and. .not. resumed
        start_kinetic = 0.0_wp
        do while (sim%time < case%time%tend - eps_t .and. .not. allocated(error))
            clock = wall_time()
            dt = min(stable_time_step(sim), case%time%tend - sim%time)
            sim%phase_time(phase_other) = sim%phase_time(phase_other) + (wall_time() - clock)
            if (governor_threads(threads) /= nthreads) then
                nthreads = governor_threads(threads)
                call set_threads(nthreads)
            end if
            step_start = wall_time()
            call advance(sim, dt, error)
            call governor_step(threads, wall_time() - step_start, wall_time())
            if (allocated(error)) then
                if (error%code == exit_numerical .and. options%write_files) then
                    call save_healthy_state(snapshot, sim%case, error)
                end if
                exit
            end if
            written = .false.
            clock = wall_time()
            if (options%write_files) then
                if (sim%time >= next_output - eps_t .or. sim%time >= case%time%tend - eps_t) then
                    call compute_energies(sim)
                    call write_part(writer, sim, error)
                    if (allocated(error)) exit
                    summary%outputs = summary%outputs + 1
                    ! (the history on disk keeps up with the particle files)
                    if (history_open) call flush_text_file(history_unit, error)
                    call agree(error)
                    if (allocated(error)) exit
                    next_output = next_output_time(next_output, case%output%interval, &
                        sim%time + eps_t)
                    written = .true.
                end if
                if (sim%time >= next_history - eps_t .or. written) then
                    call compute_energies(sim)
                    if (lead) call write_history(history_unit, sim)
                    summary%peak_kinetic = max(summary%peak_kinetic, sim%energy%kinetic)
                    next_history = sim%time + case%output%history_interval
                end if
                sim%phase_time(phase_output) = sim%phase_time(phase_output) &
                    + (wall_time() - clock)
            end if
            ! the particle counts of the images, now and then (collective: by step number)
            if (image_count() > 1 .and. mod(sim%step, int(imbalance_steps, i8)) == 0) then
                imbalance = load_imbalance(sim%particles%n)
            end if
            ! checkpoints: by step count, by wall time, and on a stop signal (collective)
            request = checkpoint_request(case, sim%step, wall_time() - t_last_checkpoint)
            ! (a run that has just finished needs none)
            if (request > 0 .and. sim%time < case%time%tend - eps_t) then
                clock = wall_time()
                ! the history up to the checkpoint is on disk before the checkpoint is: a
                ! restart keeps those lines and writes the later ones again
                if (history_open) call flush_text_file(history_unit, error)
                call agree(error)
                if (.not. allocated(error)) call write_checkpoint(checkpoint_path(case), sim, &
                    writer, next_output, next_history, wall_before + (clock - t_start), error)
                sim%phase_time(phase_output) = sim%phase_time(phase_output) &
                    + (wall_time() - clock)
                if (allocated(error)) exit
                t_last_checkpoint = wall_time()
                if (request > request_due) then
                    call fatal_error(error, "stopped by "//signal_name(request - request_due) &
                        //" at step "//int_text(sim%step)//", t = "//time_text(sim%time)// &
                        " s; the state is saved in "//checkpoint_path(case)//new_line("a")// &
                        "continue the run with: "//launcher()//"mpm_geo --restart "// &
                        checkpoint_path(case), exit_interrupted)
                    if (.not. lead) error%message = ""
                    exit
                end if
            end if
            ! (a run that has just finished needs no copy)
            if (copies .and. sim%time < case%time%tend - eps_t) then
                if (mod(sim%step, int(case%guard%snapshot_steps, i8)) == 0) then
                    clock = wall_time()
                    call take_snapshot(snapshot, sim, writer, next_output, next_history, &
                        wall_before + (clock - t_start), error)
                    sim%phase_time(phase_output) = sim%phase_time(phase_output) &
                        + (wall_time() - clock)
                    if (allocated(error)) exit
                end if
            end if
            if (.not. quiet .and. lead) call half_cell_notes(case, sim%time, noted)
            if (check_rest) then
                start_kinetic = max(start_kinetic, sim%energy%kinetic)
                if (sim%step - first_step >= equilibrium_steps .or. &
                    sim%time >= case%time%tend - eps_t) then
                    check_rest = .false.
                    if (.not. quiet) call report_rest(start_kinetic, sim%energy%initial, &
                        sim%step - first_step)
                end if
            end if
            if (.not. quiet .and. wall_time() - t_last_progress >= case%progress%interval) then
                t_last_progress = wall_time()
                call print_progress(sim, case%time%tend, t_last_progress - t_start, imbalance, &
                    first_step, first_time)
            end if
        end do
        if (case%checkpoint%on_signal) call release_stop_signals()
        ! the guard's file copy goes (left as last_healthy.h5 when the guard stopped the run)
        if (copies .and. snapshot%in_file .and. lead) then
            call remove_file(guard_copy_path(case), ignored)
            call remove_file(guard_copy_path(case)//".tmp", ignored)
        end if
        ! the parallel loops after the run (outputs, state file) and the caller's get all
        call set_threads(threads%most)
        summary%threads = governor_text(threads)
        summary%final_kinetic = sim%energy%kinetic
        summary%steps = sim%step
        summary%time = sim%time
        summary%wall = wall_time() - t_start
        summary%phase_time = sim%phase_time
        if (summary%wall > 0.0_wp) summary%particle_steps_per_second = &
            real(total, wp)*real(sim%step - first_step, wp)/summary%wall
        ! (the first failure is the one reported; the history's is agreed on here)
        if (.not. allocated(error)) then
            if (history_open) call close_text_file(history_unit, error)
            if (options%write_files) call agree(error)
        else if (history_open) then
            call close_text_file(history_unit, ignored)
        end if
        if (allocated(error)) then
            ! (an image that does not report the failure has no message)
            if (options%write_files .and. len(error%message) > 0 .and. &
                error%code /= exit_interrupted) error%message = &
                error%message//new_line("a")//"outputs written so far are in "//case%output%directory
            return
        end if

        if (has_text(case%save_state)) then
            call save_particles(sim%case%save_state, sim%case, sim%particles, sim%time, &
                sim%step, error)
            if (allocated(error)) return
        end if
        ! particle arrays, the per-step scratch (stencils, order, cell) and the guard's copy
        summary%bytes_per_particle = particle_bytes(sim%particles) + stencil_bytes(sim%stencils)
        if (copies .and. .not. snapshot%in_file) summary%bytes_per_particle = &
            summary%bytes_per_particle + particle_bytes(sim%particles)
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

    !> What the run should do after this step: nothing (0), write a checkpoint (request_due),
    !> or write one and stop (request_due + the signal number). Collective on several images
    !> (the wall clocks and the signals of the images differ: the largest request wins).
    integer function checkpoint_request(case, step, since_last)
        type(case_type), intent(in) :: case
            !! the case (checkpoint settings)
        integer(i8), intent(in) :: step
            !! steps done
        real(wp), intent(in) :: since_last
            !! wall time since the last checkpoint (or the start) [s]

        checkpoint_request = 0
        if (case%checkpoint%every_steps > 0) then
            if (mod(step, int(case%checkpoint%every_steps, i8)) == 0) checkpoint_request = request_due
        end if
        if (case%checkpoint%every_minutes > 0.0_wp) then
            if (since_last/60.0_wp >= case%checkpoint%every_minutes) checkpoint_request = &
                request_due
        end if
        if (stop_signal() /= 0) checkpoint_request = request_due + stop_signal()
        if (image_count() > 1 .and. (case%checkpoint%every_minutes > 0.0_wp .or. &
            case%checkpoint%on_signal)) call max_over_images(checkpoint_request)
    end function checkpoint_request

    !> The checkpoint file of a case: checkpoint.file, or checkpoint.h5 in the output folder.
    function checkpoint_path(case) result(path)
        type(case_type), intent(in) :: case
            !! the case
        character(len=:), allocatable :: path

        path = case%output%directory//"/checkpoint.h5"
        if (allocated(case%checkpoint%file)) then
            if (len(case%checkpoint%file) > 0) path = case%checkpoint%file
        end if
    end function checkpoint_path

    !> The output time after `now`: one interval after the `previous` one, or, when the step
    !> went past that too (an interval below the time step), the first multiple of the
    !> interval after `now`, computed directly. No loop: with an interval below the rounding
    !> of the time, adding it would not advance the schedule. An interval below the
    !> resolution of `now` gives `now`: an output every step.
    pure function next_output_time(previous, interval, now) result(next)
        real(wp), intent(in) :: previous
            !! the output time just passed [s]
        real(wp), intent(in) :: interval
            !! output interval, > 0 [s]
        real(wp), intent(in) :: now
            !! the time now, with the schedule's tolerance [s]
        real(wp) :: next
            !! the next output time [s]

        next = previous + interval
        if (next > now) return
        if (interval <= epsilon(1.0_wp)*now) then
            next = now
        else
            next = interval*(aint(now/interval) + 1.0_wp)
        end if
    end function next_output_time

    !> The run record of the simulation now (collective: the contact loads are summed).
    subroutine record_run(sim, writer, next_output, next_history, wall, run)
        type(simulation_type), intent(in) :: sim
        type(output_writer_type), intent(in) :: writer
        real(wp), intent(in) :: next_output, next_history, wall
        type(run_record_type), intent(out) :: run

        run%case_file = sim%case%file
        run%case_text = ""
        if (allocated(sim%case%text)) run%case_text = sim%case%text
        run%output_dir = sim%case%output%directory
        run%images = image_count()
        run%dt = sim%dt
        run%energy = energy_record(sim%energy)
        run%kinetic_previous = sim%kinetic_previous
        run%next_output = next_output
        run%next_history = next_history
        run%wall = wall
        call output_list(writer, run%output_time, run%output_step, run%output_counts, &
            run%output_id)
        call contact_loads(sim, run%face_load, run%terrain_node, run%terrain_load)
        ! the springs' stretch of Kelvin-Voigt faces (one image)
        if (sim%case%domain%has_springs(sim%case%dim)) run%acting_disp = reshape(sim%grid%acting_disp, &
            [size(sim%grid%acting_disp)])
        ! a one-pass run: the order of the P2G its last step did for the next
        if (sim%scatter_ready) run%scatter_order = sim%stencils%order
    end subroutine record_run

    !> Write a checkpoint of the run now (collective).
    subroutine write_checkpoint(path, sim, writer, next_output, next_history, wall, error)
        character(len=*), intent(in) :: path
            !! checkpoint file (written through path.tmp and a rename)
        type(simulation_type), intent(in) :: sim
            !! the simulation
        type(output_writer_type), intent(in) :: writer
            !! the run's writer (the outputs written so far)
        real(wp), intent(in) :: next_output, next_history, wall
            !! output schedule and wall time of the run so far
        type(error_type), allocatable, intent(out) :: error
            !! set on every image when the file cannot be written

        type(run_record_type) :: run

        call record_run(sim, writer, next_output, next_history, wall, run)
        call save_particles(path, sim%case, sim%particles, sim%time, sim%step, error, run)
    end subroutine write_checkpoint

    !> Keep a copy of the state after a healthy step (collective): a checkpoint written to
    !> guard_copy_path (through a .tmp file and a rename, so the last complete copy survives a
    !> failed write), or the particles and the run record in memory.
    subroutine take_snapshot(snapshot, sim, writer, next_output, next_history, wall, error)
        type(snapshot_type), intent(inout) :: snapshot
        type(simulation_type), intent(in) :: sim
        type(output_writer_type), intent(in) :: writer
        real(wp), intent(in) :: next_output, next_history, wall
        type(error_type), allocatable, intent(out) :: error
            !! set (on every image) when the file copy cannot be written

        if (snapshot%in_file) then
            call write_checkpoint(guard_copy_path(sim%case), sim, writer, next_output, &
                next_history, wall, error)
            if (allocated(error)) then
                error%message = "the blow-up guard cannot keep its copy of the state: "// &
                    error%message//new_line("a")//"make room on that disk, or keep the copy "// &
                    "in memory (""guard"": {""snapshot_in"": ""memory""}) or none "// &
                    "(""guard"": {""snapshot_steps"": 0})"
                if (image_id() /= 1) error%message = ""
                return
            end if
        else
            snapshot%particles = sim%particles
            call record_run(sim, writer, next_output, next_history, wall, snapshot%run)
        end if
        snapshot%time = sim%time
        snapshot%step = sim%step
        snapshot%taken = .true.
    end subroutine take_snapshot

    !> The guard's file copy of the state: a hidden checkpoint in the output folder.
    function guard_copy_path(case) result(path)
        type(case_type), intent(in) :: case
            !! the case
        character(len=:), allocatable :: path

        path = case%output%directory//"/.last_healthy.h5"
    end function guard_copy_path

    !> After the guard stopped the run: write the last copy of a healthy state as a
    !> checkpoint beside the outputs and say so in the message (collective).
    subroutine save_healthy_state(snapshot, case, error)
        type(snapshot_type), intent(in) :: snapshot
            !! the last healthy copy
        type(case_type), intent(in) :: case
            !! the case
        type(error_type), allocatable, intent(inout) :: error
            !! the guard's error; its message gets the file's name

        type(error_type), allocatable :: failed
        character(len=:), allocatable :: path

        if (.not. snapshot%taken) return
        path = case%output%directory//"/last_healthy.h5"
        if (snapshot%in_file) then
            if (image_id() == 1) call rename_file(guard_copy_path(case), path, failed)
            call agree(failed)
        else
            call save_particles(path, case, snapshot%particles, snapshot%time, snapshot%step, &
                failed, snapshot%run)
        end if
        if (len(error%message) == 0) return
        if (allocated(failed)) then
            error%message = error%message//new_line("a")//"the last healthy state could "// &
                "not be saved: "//failed%message
        else
            error%message = error%message//new_line("a")//"the last healthy state (step "// &
                int_text(snapshot%step)//", t = "//time_text(snapshot%time)//" s) is saved in " &
                //path//"; look at it, or continue from it with another time step: "// &
                launcher()//"mpm_geo CASE.json --restart "//path
        end if
    end subroutine save_healthy_state

    !> The particles of the run in a state file (collective): on several images, image 1
    !> collects every particle, in the order of the ids (the order of one image), and writes
    !> the file. With `run` the file is a checkpoint.
    subroutine save_particles(path, case, particles, time, step, error, run)
        character(len=*), intent(in) :: path
            !! file to write
        type(case_type), intent(in) :: case
            !! the case
        type(particles_type), intent(in) :: particles
            !! this image's particles
        real(wp), intent(in) :: time
            !! simulated time [s]
        integer(i8), intent(in) :: step
            !! steps done
        type(error_type), allocatable, intent(out) :: error
            !! set (on every image) when the state cannot be written
        type(run_record_type), intent(in), optional :: run
            !! the run record, for a checkpoint

        type(particles_type) :: all
        real(wp), allocatable :: mine(:), records(:), ordered(:)
        integer :: r, q, k, n

        if (image_count() == 1) then
            call save_state(path, case, particles, time, int(step), error, run)
            return
        end if
        call pack_particles(particles, [(.true., q = 1, particles%n)], mine)
        call gather_on_first(mine, records)
        if (image_id() == 1) then
            ! records in id order (the id is the last value of a record)
            r = record_length(particles)
            n = size(records)/r
            allocate (ordered(size(records)))
            do q = 1, n
                k = nint(records(q*r))
                ordered((k - 1)*r + 1:k*r) = records((q - 1)*r + 1:q*r)
            end do
            all = particles
            call rebuild_particles(all, [(.false., q = 1, all%n)], ordered, error)
            if (.not. allocated(error)) then
                deallocate (all%id)
                call save_state(path, case, all, time, int(step), error, run)
            end if
        end if
        call agree(error)
    end subroutine save_particles

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

    !> The output folder of a run that goes on from a checkpoint: it must be there; the lines
    !> of the energy history after the checkpoint's step (written before the run stopped)
    !> are dropped, as the run writes them again.
    subroutine resume_output_dir(case, step, lock, error)
        type(case_type), intent(in) :: case
            !! the case (output folder)
        integer(i8), intent(in) :: step
            !! step of the checkpoint
        type(folder_lock_type), intent(inout) :: lock
            !! the lock of the folder, taken before anything in it changes
        type(error_type), allocatable, intent(out) :: error
            !! set when the folder is missing, another run holds it or the history cannot
            !! be rewritten

        character(len=:), allocatable :: path
        character(len=4096) :: line
        character(len=256) :: msg
        integer :: input, stat, comma, last
        type(text_file_type) :: output
        type(error_type), allocatable :: ignored
        integer(i8) :: row_step
        logical :: keep

        if (.not. directory_exists(case%output%directory)) then
            call fatal_error(error, "the output folder of the run, '"//case%output%directory// &
                "', is missing: a restart continues the outputs of the run in its folder", &
                exit_input)
            return
        end if
        call lock_folder(case%output%directory, lock, error)
        if (allocated(error)) return
        path = case%output%directory//"/history.csv"
        if (.not. file_exists(path)) return
        open (newunit=input, file=path, status="old", action="read", iostat=stat, iomsg=msg)
        if (stat /= 0) then
            call fatal_error(error, path//": "//trim(msg), exit_other)
            return
        end if
        call open_text_file(path//".tmp", output, error, shown_as=path)
        if (allocated(error)) then
            close (input)
            return
        end if
        do
            read (input, "(a)", iostat=stat, iomsg=msg) line
            if (stat /= 0) exit
            last = len_trim(line)
            ! rows are "time,step,...": keep the header and the rows up to the step
            keep = .true.
            comma = index(line(1:last), ",")
            if (comma > 0 .and. verify(line(1:1), "0123456789+-. ") == 0) then
                read (line(comma + 1:), *, iostat=stat, iomsg=msg) row_step
                keep = stat /= 0 .or. row_step <= step
            end if
            if (keep) call put_line(output, line(1:last))
        end do
        close (input)
        call close_text_file(output, error)
        if (allocated(error)) then
            ! the history of the run stays as it was
            call remove_file(path//".tmp", ignored)
            return
        end if
        call rename_file(path//".tmp", path, error)
    end subroutine resume_output_dir

    !> How the run was started, for the commands messages suggest: "" on one image,
    !> "cafrun -np N " on several (a restart needs as many images).
    function launcher() result(text)
        character(len=:), allocatable :: text

        text = ""
        if (image_count() > 1) text = "cafrun -np "//int_text(image_count())//" "
    end function launcher

    !> A simulated time for messages, "2.92534E-02".
    function time_text(t) result(text)
        real(wp), intent(in) :: t
            !! time [s]
        character(len=:), allocatable :: text

        character(len=16) :: buf

        write (buf, "(es12.5)") t
        text = trim(adjustl(buf))
    end function time_text

    !> Create the output folder; refuse an existing one unless overwriting was asked for, and
    !> one another run holds. The lock is taken before anything in the folder is removed.
    subroutine prepare_output_dir(case, lock, error)
        type(case_type), intent(in) :: case
        type(folder_lock_type), intent(inout) :: lock
            !! the lock of the folder, held by the caller for the run
        type(error_type), allocatable, intent(out) :: error

        if (directory_exists(case%output%directory) .and. .not. case%output%overwrite) then
            call fatal_error(error, "output folder '"//case%output%directory//"' exists already; "// &
                "mpm_geo does not overwrite results: pass --overwrite (or set "// &
                """output"": {""overwrite"": true}), or choose another folder with --output DIR", &
                exit_input)
            return
        end if
        call make_directory(case%output%directory, error)
        if (allocated(error)) return
        call lock_folder(case%output%directory, lock, error)
        if (allocated(error)) return
        call remove_outputs(case%output%directory, case%name, error)
        if (allocated(error)) return
        ! an earlier run's checkpoints would continue that run in this one's folder
        call remove_file(case%output%directory//"/checkpoint.h5", error)
        if (.not. allocated(error)) call remove_file(case%output%directory//"/checkpoint.h5.tmp", error)
        if (.not. allocated(error)) call remove_file(case%output%directory//"/last_healthy.h5", error)
        if (.not. allocated(error)) call remove_file(case%output%directory//"/last_healthy.h5.tmp", &
            error)
        if (.not. allocated(error)) call remove_file(guard_copy_path(case), error)
        if (.not. allocated(error)) call remove_file(guard_copy_path(case)//".tmp", error)
    end subroutine prepare_output_dir

    !> Whether a geostatic start (initial_stress.type = "k0") is at rest: the largest kinetic
    !> energy of its first steps against the energy it starts with (its elastic energy).
    subroutine report_rest(kinetic, initial, steps)
        real(wp), intent(in) :: kinetic
            !! largest kinetic energy of those steps [J]
        real(wp), intent(in) :: initial
            !! the energy at the start (kinetic + elastic) [J]
        integer(i8), intent(in) :: steps
            !! the steps

        real(wp), parameter :: at_rest = 1.0e-6_wp
            !! largest ratio reported as equilibrium: round-off gives about 1e-30, a slope's
            !! K0 state 1e-4 and more
        real(wp) :: ratio

        ratio = kinetic/max(initial, tiny(1.0_wp))
        write (output_unit, "(a,i0,a,es9.2,a)") "mpm_geo: initial stress k0: the largest " &
            //"kinetic energy of the first ", steps, " steps is ", ratio, " of the elastic " &
            //"energy at the start"
        if (ratio <= at_rest) then
            write (output_unit, "(a)") "  the ground starts at rest (in equilibrium)"
        else
            write (output_unit, "(a)") "  the ground is not in equilibrium at the start (the " &
                //"K0 state of a slope, or a K0 beyond a material's strength): it moves " &
                //"towards it; a damped first stage reaches it (docs/input.md, initial_stress)"
        end if
    end subroutine report_rest

    subroutine print_progress(sim, tend, elapsed, imbalance, first_step, first_time)
        type(simulation_type), intent(in) :: sim
        real(wp), intent(in) :: tend, elapsed
        real(wp), intent(in) :: imbalance
            !! largest particle count of an image over the mean (0: one image)
        integer(i8), intent(in) :: first_step
            !! step at the start of this process (a restart starts later)
        real(wp), intent(in) :: first_time
            !! simulated time at the start of this process [s]

        real(wp) :: rate, eta

        rate = real(sim%step - first_step, wp)/max(elapsed, 1.0e-9_wp)
        eta = elapsed*(tend - sim%time)/max(sim%time - first_time, tiny(1.0_wp))
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
        if (allocated(summary%threads)) write (output_unit, "(a)") "  threads              "// &
            summary%threads
        write (output_unit, "(a,i0,a)") "  output files         ", summary%outputs, &
            " in "//case%output%directory
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
