!> mpm_geo: command line of the explicit MPM solver. Parses the arguments, reads the case,
!> runs it, and turns errors into a message on standard error and an exit code:
!> 0 success, 1 other errors, 2 invalid input, 3 numerical failure.
program mpm_geo_main
    use, intrinsic :: iso_fortran_env, only: error_unit, output_unit
    use mpm_error, only: error_type, fatal_error, exit_input
    use mpm_version, only: mpm_version_string
    use mpm_case, only: case_type, read_case_file, case_summary
    use mpm_run, only: run_options_type, run_summary_type, run_case
    use mpm_solver, only: simulation_type
    use mpm_parallel, only: image_id, end_images
    implicit none

    type(error_type), allocatable :: error
    type(case_type) :: case
    type(run_options_type) :: options
    type(run_summary_type) :: summary
    type(simulation_type) :: sim
    character(len=:), allocatable :: case_path, output_dir
    logical :: check_only, overwrite, done
    logical :: before_run = .true.
        !! errors so far are the same on every image (arguments, case file)

    call parse_arguments(case_path, output_dir, check_only, overwrite, options, done, error)
    if (allocated(error)) call fail(error)
    if (done) stop

    call read_case_file(case_path, case, error)
    if (allocated(error)) call fail(error)
    if (allocated(output_dir)) case%output_dir = output_dir
    if (overwrite) case%overwrite = .true.

    if (check_only) then
        if (image_id() == 1) then
            write (output_unit, "(a)") case_summary(case)
            write (output_unit, "(a)") "mpm_geo: "//case_path//" is valid (--check: nothing "// &
                "was run)"
        end if
        stop
    end if

    before_run = .false.
    call run_case(case, options, sim, summary, error)
    if (allocated(error)) call fail(error)
    call end_images(0)

contains

    !> Print an error and exit with its code. On several images every image calls it; the
    !> failures of the run are agreed on, and only the image that reports one has a message
    !> (errors before the run, the same on every image, are printed by image 1).
    subroutine fail(err)
        type(error_type), intent(in) :: err

        if (len(err%message) > 0 .and. (image_id() == 1 .or. .not. before_run)) then
            write (error_unit, "(a)") "mpm_geo: error: "//err%message
            flush (error_unit)
        end if
        call end_images(err%code)
        stop err%code, quiet=.true.
    end subroutine fail

    subroutine parse_arguments(case_path, output_dir, check_only, overwrite, options, done, error)
        character(len=:), allocatable, intent(out) :: case_path, output_dir
        logical, intent(out) :: check_only, overwrite
        type(run_options_type), intent(inout) :: options
        logical, intent(out) :: done
        type(error_type), allocatable, intent(out) :: error

        integer :: i, n
        character(len=:), allocatable :: arg

        check_only = .false.
        overwrite = .false.
        done = .false.
        n = command_argument_count()
        i = 0
        do while (i < n)
            i = i + 1
            arg = argument(i)
            select case (arg)
            case ("-h", "--help")
                if (image_id() == 1) call print_help()
                done = .true.
                return
            case ("-V", "--version")
                if (image_id() == 1) write (output_unit, "(a)") "mpm_geo "//mpm_version_string
                done = .true.
                return
            case ("--check")
                check_only = .true.
            case ("-q", "--quiet")
                options%quiet = .true.
            case ("--overwrite")
                overwrite = .true.
            case ("-i", "--input", "-o", "--output")
                if (i == n) then
                    call fatal_error(error, "option "//arg//" needs a value; see mpm_geo --help", &
                        exit_input)
                    return
                end if
                i = i + 1
                if (arg == "-i" .or. arg == "--input") then
                    if (allocated(case_path)) then
                        call fatal_error(error, "more than one case file given ('"//case_path// &
                            "' and '"//argument(i)//"'); mpm_geo runs one case", exit_input)
                        return
                    end if
                    case_path = argument(i)
                else
                    output_dir = argument(i)
                    if (len(output_dir) == 0) then
                        call fatal_error(error, "--output needs a folder name", exit_input)
                        return
                    end if
                end if
            case default
                if (len(arg) > 0) then
                    if (arg(1:1) == "-") then
                        call fatal_error(error, "unknown option '"//arg//"'; allowed: --input, "// &
                            "--output, --check, --overwrite, --quiet, --help, --version", &
                            exit_input)
                        return
                    end if
                end if
                if (allocated(case_path)) then
                    call fatal_error(error, "more than one case file given ('"//case_path// &
                        "' and '"//arg//"'); mpm_geo runs one case", exit_input)
                    return
                end if
                case_path = arg
            end select
        end do
        if (.not. allocated(case_path)) then
            call fatal_error(error, "no case file given; usage: mpm_geo CASE.json "// &
                "(mpm_geo --help for all options)", exit_input)
        end if
    end subroutine parse_arguments

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
            "", &
            "options:", &
            "  -i, --input FILE   case file (JSON; keys in docs/input.md)", &
            "  -o, --output DIR   output folder (default: outputs/<case name>)", &
            "      --overwrite    allow writing into an existing output folder", &
            "      --check        read and validate the case, print the resolved set-up, run nothing", &
            "  -q, --quiet        no progress lines and no summary", &
            "  -h, --help         this help", &
            "  -V, --version      print the version", &
            "", &
            "exit codes: 0 success, 1 other errors, 2 invalid input, 3 numerical failure", &
            "threads: set OMP_NUM_THREADS (default: all cores)", &
            "images: cafrun -np N mpm_geo CASE.json with the coarray build (make coarray; "// &
            "docs/hpc.md)"
    end subroutine print_help

end program mpm_geo_main
