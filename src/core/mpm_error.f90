!> Error handling: library code never stops, it returns an error_type.
!>
!> The pattern follows mctc-lib and fpm: a procedure takes
!> `type(error_type), allocatable, intent(out) :: error`, calls `fatal_error` and returns;
!> callers test `if (allocated(error)) return`. Only the main program turns an error into a
!> message and an exit code.
module mpm_error
    implicit none
    private
    public :: error_type, fatal_error
    public :: exit_success, exit_other, exit_input, exit_numerical, exit_interrupted, &
        exit_output

    integer, parameter :: exit_success = 0
        !! process exit code: success
    integer, parameter :: exit_other = 1
        !! process exit code: any other error (I/O, out of memory, ...)
    integer, parameter :: exit_input = 2
        !! process exit code: invalid input (case file, state file, command line)
    integer, parameter :: exit_numerical = 3
        !! process exit code: numerical failure (instability, NaN)
    integer, parameter :: exit_interrupted = 4
        !! process exit code: stopped by SIGTERM or SIGINT after writing a checkpoint (the run
        !! continues with mpm_geo --restart)
    integer, parameter :: exit_output = 5
        !! process exit code: an output file could not be written (a full disk, a quota, a
        !! write error); the outputs written before it are complete

    !> An error with a message for the user and the exit code it maps to.
    type :: error_type
        character(len=:), allocatable :: message
            !! complete message for the user, one or more lines
        integer :: code = exit_other
            !! exit code the main program uses for this error
    end type error_type

contains

    !> Allocate `error` with a message and an exit code (default: exit_other).
    pure subroutine fatal_error(error, message, code)
        type(error_type), allocatable, intent(out) :: error
            !! the error to create
        character(len=*), intent(in) :: message
            !! what went wrong, what was expected
        integer, intent(in), optional :: code
            !! exit code (exit_input, exit_numerical, exit_output, exit_other)

        allocate (error)
        error%message = message
        if (present(code)) error%code = code
    end subroutine fatal_error

end module mpm_error
