!> The mpm_geo program, command line of the explicit MPM solver. Parses the arguments, reads
!> the case, runs it, and turns errors into a message on standard error and an exit code:
!> 0 success, 1 other errors, 2 invalid input, 3 numerical failure, 4 stopped by a signal
!> after writing a checkpoint, 5 an output file could not be written (a full disk).
program mpm_geo_main
    use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
    use, intrinsic :: ieee_exceptions, only: ieee_overflow, ieee_get_halting_mode, &
        ieee_set_halting_mode, ieee_set_flag
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_input, exit_interrupted
    use mpm_version, only: mpm_version_string
    use mpm_case, only: case_type, read_case_file, read_case_string, case_summary
    use mpm_run, only: run_options_type, run_summary_type, run_case, checkpoint_path
    use mpm_strength_reduction, only: strength_reduction_result_type, run_strength_reduction
    use mpm_solver, only: simulation_type
    use mpm_state, only: run_record_type, read_run_record, load_state
    use mpm_particles, only: particles_type
    use mpm_parallel, only: image_id, image_count, end_images
    use mpm_strings, only: int_text, path_problem, max_name_bytes, text_or
    use mpm_shape, only: shape_type
    use mpm_shape_factory, only: new_shape
    implicit none

    !> What the command line asks for.
    type :: command_type
        character(len=:), allocatable :: case_path
            !! case file
        character(len=:), allocatable :: output_dir
            !! --output
        logical :: check_only = .false.
            !! --check
        logical :: overwrite = .false.
            !! --overwrite
        logical :: restart = .false.
            !! --restart
        character(len=:), allocatable :: restart_path
            !! --restart FILE ("" for the checkpoint of the case)
        integer :: checkpoint_steps = -1
            !! --checkpoint-steps N (-1: the case's)
        real(wp) :: checkpoint_minutes = -1.0_wp
            !! --checkpoint-minutes T (-1: the case's)
        logical :: done = .false.
            !! --help or --version answered
    end type command_type

    type(error_type), allocatable :: error
    type(case_type) :: case
    type(run_options_type) :: options
    type(run_summary_type) :: summary
    type(simulation_type) :: sim
    type(command_type) :: cmd
    type(run_record_type) :: run
    type(particles_type) :: particles
    type(strength_reduction_result_type) :: reduction
    class(shape_type), allocatable :: shape
    real(wp) :: state_time
    integer :: state_step
    logical :: before_run = .true.
        !! errors so far are the same on every image (arguments, case file)

    call parse_arguments(cmd, options, error)
    if (allocated(error)) call fail(error)
    if (cmd%done) stop

    if (cmd%restart) then
        call read_restart(cmd, case, run, error)
    else
        call read_case_file(cmd%case_path, case, error)
    end if
    if (allocated(error)) call fail(error)
    ! solver.shape_function: the registry of the shape functions lies above the case layer,
    ! so its name is checked here (and --check refuses a name no shape function has)
    call new_shape(shape, trim(case%solver%shape_function), error, text_or(case%file, "?"))
    if (allocated(error)) call fail(error)
    if (allocated(cmd%output_dir)) case%output%directory = cmd%output_dir
    if (cmd%overwrite) case%output%overwrite = .true.
    if (cmd%checkpoint_steps >= 0) case%checkpoint%every_steps = cmd%checkpoint_steps
    if (cmd%checkpoint_minutes >= 0.0_wp) case%checkpoint%every_minutes = cmd%checkpoint_minutes

    if (cmd%check_only) then
        ! a checkpoint: its particles must fit the case (grid, materials, domain)
        if (cmd%restart) then
            call load_state(cmd%restart_path, case, particles, state_time, state_step, error)
            if (allocated(error)) then
                error%message = "cannot restart from '"//cmd%restart_path//"': "// &
                    error%message
                call fail(error)
            end if
            if (image_id() == 1) write (output_unit, "(a,i0,a)") "mpm_geo: the checkpoint '"// &
                cmd%restart_path//"' (step ", state_step, ") fits the case"
        end if
        if (image_id() == 1) then
            write (output_unit, "(a)") case_summary(case)
            write (output_unit, "(a)") "mpm_geo: "//case%file//" is valid (--check: nothing "// &
                "was run)"
        end if
        stop
    end if

    before_run = .false.
    if (case%strength_reduction%enabled) then
        if (cmd%restart) then
            call fatal_error(error, case%file//": --restart continues one run; a strength "// &
                "reduction (strength_reduction) runs many: run the case again into a new "// &
                "folder", exit_input)
        else
            call run_strength_reduction(case, options, reduction, error)
        end if
    else if (cmd%restart) then
        call run_case(case, options, sim, summary, error, cmd%restart_path, run)
    else
        call run_case(case, options, sim, summary, error)
    end if
    if (allocated(error)) call fail(error)
    call end_images(0)

contains

    !> Print an error and exit with its code. On several images every image calls it; the
    !> failures of the run are agreed on, and only the image that reports one has a message
    !> (errors before the run, the same on every image, are printed by image 1).
    subroutine fail(err)
        type(error_type), intent(in) :: err

        if (len(err%message) > 0 .and. (image_id() == 1 .or. .not. before_run)) then
            if (err%code == exit_interrupted) then
                write (error_unit, "(a)") "mpm_geo: "//err%message
            else
                write (error_unit, "(a)") "mpm_geo: error: "//err%message
            end if
            flush (error_unit)
        end if
        call end_images(err%code)
        stop err%code, quiet=.true.
    end subroutine fail

    !> The case and the run record of a restart. The case is the one the checkpoint keeps,
    !> or the case file given on the command line (to change, say, tend or the time step);
    !> the run goes on in the checkpoint's output folder.
    subroutine read_restart(cmd, case, run, error)
        type(command_type), intent(inout) :: cmd
        type(case_type), intent(out) :: case
        type(run_record_type), intent(out) :: run
        type(error_type), allocatable, intent(out) :: error

        if (len(cmd%restart_path) == 0) then
            ! the checkpoint of the case given
            if (.not. allocated(cmd%case_path)) then
                call fatal_error(error, "--restart needs a checkpoint file, or a case file "// &
                    "whose checkpoint to continue: mpm_geo --restart outputs/CASE/"// &
                    "checkpoint.h5, or mpm_geo CASE.json --restart", exit_input)
                return
            end if
            call read_case_file(cmd%case_path, case, error)
            if (allocated(error)) return
            if (allocated(cmd%output_dir)) case%output%directory = cmd%output_dir
            cmd%restart_path = checkpoint_path(case)
        end if
        call read_run_record(cmd%restart_path, run, error)
        if (allocated(error)) return
        if (run%images /= image_count()) then
            call fatal_error(error, "cannot restart from '"//cmd%restart_path//"': it was "// &
                "written by a run on "//int_text(run%images)//" image(s), this one has "// &
                int_text(image_count())//"; restart it on as many images, or start a new "// &
                "run from it with load_state in the case file", exit_input)
            return
        end if
        if (allocated(cmd%output_dir)) then
            if (cmd%output_dir /= run%output_dir) then
                call fatal_error(error, "--restart continues the run in its output folder '"// &
                    run%output_dir//"'; --output cannot move it", exit_input)
                return
            end if
        end if
        if (allocated(cmd%case_path)) then
            if (.not. allocated(case%file)) then
                call read_case_file(cmd%case_path, case, error)
                if (allocated(error)) return
            end if
            if (case%text /= run%case_text .and. image_id() == 1 .and. &
                .not. options%quiet) then
                write (output_unit, "(a)") "mpm_geo: note: "//cmd%case_path//" is not the "// &
                    "case file the checkpoint was written with ("//run%case_file//"); the "// &
                    "run goes on with "//cmd%case_path//" as it is now"
            end if
        else
            call read_case_string(run%case_text, case, error, run%case_file)
            if (allocated(error)) then
                error%message = "the case kept in the checkpoint '"//cmd%restart_path// &
                    "': "//error%message
                return
            end if
            case%file = run%case_file
        end if
        case%output%directory = run%output_dir
        cmd%output_dir = run%output_dir
    end subroutine read_restart

    subroutine parse_arguments(cmd, options, error)
        type(command_type), intent(inout) :: cmd
        type(run_options_type), intent(inout) :: options
        type(error_type), allocatable, intent(out) :: error

        integer :: i, n, stat
        character(len=:), allocatable :: arg, value
        character(len=256) :: msg
        logical :: halting

        n = command_argument_count()
        i = 0
        do while (i < n)
            i = i + 1
            arg = argument(i)
            select case (arg)
            case ("-h", "--help")
                if (image_id() == 1) call print_help()
                cmd%done = .true.
                return
            case ("-V", "--version")
                if (image_id() == 1) write (output_unit, "(a)") "mpm_geo "//mpm_version_string
                cmd%done = .true.
                return
            case ("--check")
                cmd%check_only = .true.
            case ("-q", "--quiet")
                options%quiet = .true.
            case ("--overwrite")
                cmd%overwrite = .true.
            case ("--restart")
                cmd%restart = .true.
                cmd%restart_path = ""
                ! an optional value: the checkpoint (not an option, not a case file)
                if (i < n) then
                    value = argument(i + 1)
                    if (len(value) > 0) then
                        if (value(1:1) /= "-" .and. .not. ends_with(value, ".json")) then
                            cmd%restart_path = value
                            i = i + 1
                        end if
                    end if
                end if
            case ("-i", "--input", "-o", "--output", "--checkpoint-steps", &
                  "--checkpoint-minutes")
                if (i == n) then
                    call fatal_error(error, "option "//arg//" needs a value; see mpm_geo --help", &
                        exit_input)
                    return
                end if
                i = i + 1
                value = argument(i)
                ! an option is not a value ("-o --check" must not run into a folder "--check");
                ! a file or folder whose name starts with "-" is given as ./-name
                if (starts_option(value, numeric=index(arg, "--checkpoint") == 1)) then
                    call fatal_error(error, "option "//arg//" needs a value, got the option '"// &
                        value//"'; see mpm_geo --help", exit_input)
                    return
                end if
                select case (arg)
                case ("-i", "--input")
                    call set_case_path(cmd, value, error)
                    if (allocated(error)) return
                case ("--checkpoint-steps")
                    ! the characters first: a read accepts more than a count of steps
                    stat = 1
                    if (verify(value, "0123456789") == 0) read (value, *, iostat=stat, &
                        iomsg=msg) cmd%checkpoint_steps
                    if (stat /= 0) cmd%checkpoint_steps = 0
                    if (cmd%checkpoint_steps < 1) then
                        call fatal_error(error, "--checkpoint-steps "//value//": must be "// &
                            "a whole number of steps >= 1", exit_input)
                        return
                    end if
                case ("--checkpoint-minutes")
                    ! (no "nan" or "inf" gets through the characters; an overflow, 1e999,
                    ! reads as infinity, without the trap of a debug build)
                    stat = 1
                    call ieee_get_halting_mode(ieee_overflow, halting)
                    call ieee_set_halting_mode(ieee_overflow, .false.)
                    if (verify(value, "0123456789.eE+-") == 0) read (value, *, iostat=stat, &
                        iomsg=msg) cmd%checkpoint_minutes
                    call ieee_set_flag(ieee_overflow, .false.)
                    call ieee_set_halting_mode(ieee_overflow, halting)
                    if (stat /= 0) cmd%checkpoint_minutes = 0.0_wp
                    if (.not. (cmd%checkpoint_minutes > 0.0_wp .and. &
                        cmd%checkpoint_minutes <= huge(1.0_wp))) then
                        call fatal_error(error, "--checkpoint-minutes "//value//": must be "// &
                            "a number of minutes > 0", exit_input)
                        return
                    end if
                case default
                    cmd%output_dir = value
                    if (len(cmd%output_dir) == 0) then
                        call fatal_error(error, "--output needs a folder name", exit_input)
                        return
                    end if
                    ! room for "/" and a file name in the folder
                    if (len(path_problem(value, 1 + max_name_bytes, 0)) > 0) then
                        call fatal_error(error, "--output "//value(1:min(len(value), 40))// &
                            repeat(".", merge(3, 0, len(value) > 40))// &
                            ": not a usable folder name: "// &
                            path_problem(value, 1 + max_name_bytes, 0), exit_input)
                        return
                    end if
                end select
            case default
                if (len(arg) > 0) then
                    if (arg(1:1) == "-") then
                        call fatal_error(error, "unknown option '"//arg//"'; allowed: --input, "// &
                            "--output, --check, --overwrite, --quiet, --restart, "// &
                            "--checkpoint-steps, --checkpoint-minutes, --help, --version", &
                            exit_input)
                        return
                    end if
                end if
                call set_case_path(cmd, arg, error)
                if (allocated(error)) return
            end select
        end do
        if (.not. allocated(cmd%case_path) .and. .not. cmd%restart) then
            call fatal_error(error, "no case file given; usage: mpm_geo CASE.json "// &
                "(mpm_geo --help for all options)", exit_input)
        end if

    end subroutine parse_arguments

    subroutine set_case_path(cmd, path, error)
        type(command_type), intent(inout) :: cmd
        character(len=*), intent(in) :: path
        type(error_type), allocatable, intent(out) :: error

        if (allocated(cmd%case_path)) then
            call fatal_error(error, "more than one case file given ('"//cmd%case_path// &
                "' and '"//path//"'); mpm_geo runs one case", exit_input)
            return
        end if
        cmd%case_path = path
    end subroutine set_case_path

    !> Whether a command-line word is an option, not the value of the option before it: it
    !> starts with "-" (for a `numeric` option, "--": "-5" is a number, and refused as one).
    pure logical function starts_option(word, numeric)
        character(len=*), intent(in) :: word
            !! the word after an option that takes a value
        logical, intent(in) :: numeric
            !! the option takes a number
        if (numeric) then
            starts_option = len(word) >= 2
            if (starts_option) starts_option = word(1:2) == "--"
        else
            starts_option = len(word) >= 1
            if (starts_option) starts_option = word(1:1) == "-"
        end if
    end function starts_option

    pure logical function ends_with(text, tail)
        character(len=*), intent(in) :: text, tail
        ends_with = .false.
        if (len(text) >= len(tail)) ends_with = text(len(text) - len(tail) + 1:) == tail
    end function ends_with

    function argument(i) result(arg)
        integer, intent(in) :: i
        character(len=:), allocatable :: arg

        integer :: length

        call get_command_argument(i, length=length)
        allocate (character(len=length) :: arg)
        if (length > 0) call get_command_argument(i, arg)
    end function argument

    subroutine print_help()
        write (output_unit, "(a)") &
            "mpm_geo "//mpm_version_string//" - explicit Material Point Method for geomechanics", &
            "", &
            "usage: mpm_geo [options] CASE.json", &
            "       mpm_geo [options] --input CASE.json", &
            "       mpm_geo --restart outputs/CASE/checkpoint.h5", &
            "", &
            "options:", &
            "  -i, --input FILE   case file (JSON; keys in docs/input.md)", &
            "  -o, --output DIR   output folder (default: outputs/<case name>)", &
            "      --overwrite    allow writing into an existing output folder", &
            "      --check        read and validate the case, print the resolved set-up, run nothing", &
            "  -q, --quiet        no progress lines and no summary", &
            "      --checkpoint-steps N    write a checkpoint every N steps", &
            "      --checkpoint-minutes T  write a checkpoint every T minutes of wall time", &
            "      --restart [FILE]        continue a run from its checkpoint FILE (default: the", &
            "                     case's, outputs/<case name>/checkpoint.h5); with CASE.json the", &
            "                     run goes on with that case file, else with the one kept in FILE", &
            "  -h, --help         this help", &
            "  -V, --version      print the version", &
            "a FILE or DIR whose name starts with '-' would be taken for an option: write ./-name", &
            "", &
            "SIGTERM or SIGINT (Ctrl-C) during a run: a checkpoint is written and the run stops", &
            "with exit code 4 (a second signal stops it at once).", &
            "exit codes: 0 success, 1 other errors, 2 invalid input (also: the output folder is", &
            "            in use by another run), 3 numerical failure, 4 stopped by a signal", &
            "            after writing a checkpoint, 5 an output file could not be written", &
            "            (a full disk: no space left on device)", &
            "threads: OMP_NUM_THREADS sets the most (default: all cores); each step uses as", &
            "         many as run fastest (fewer on busy cores); OMP_DYNAMIC=false: all", &
            "images: cafrun -np N mpm_geo CASE.json with the coarray build (make coarray; "// &
            "docs/hpc.md)"
    end subroutine print_help

end program mpm_geo_main
