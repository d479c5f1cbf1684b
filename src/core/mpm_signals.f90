!> Stop requests from the operating system: SIGTERM (what Slurm and most batch systems send
!> before a job's time limit) and SIGINT (Ctrl-C).
!>
!> While the requests are caught, the handler only records the signal; the time loop looks
!> at it after each step, writes a checkpoint and stops cleanly. The handler also gives both
!> signals back their default action, so a second Ctrl-C or SIGTERM (while the checkpoint is
!> written, say) ends the process at once; the checkpoint is written to a temporary
!> file and renamed, so the previous one stays readable.
!>
!> The C `signal` function is called through iso_c_binding; the signal numbers are those of
!> Linux and macOS (POSIX leaves them to the system, but 2 and 15 are universal in practice).
module mpm_signals
    use, intrinsic :: iso_c_binding, only: c_int, c_funptr, c_funloc, c_null_funptr
    implicit none
    private
    public :: catch_stop_signals, release_stop_signals, stop_signal, signal_name
    public :: sigint, sigterm

    integer(c_int), parameter :: sigint = 2
        !! interrupt from the keyboard (Ctrl-C)
    integer(c_int), parameter :: sigterm = 15
        !! termination request (kill, Slurm at the time limit, scancel)

    integer(c_int), volatile :: received = 0
        !! the last stop signal received since catch_stop_signals, 0 if none

    interface
        !> void (*signal(int signum, void (*handler)(int)))(int), from the C library
        function c_signal(signum, handler) bind(c, name="signal") result(previous)
            import :: c_int, c_funptr
            integer(c_int), value :: signum
            type(c_funptr), value :: handler
            type(c_funptr) :: previous
        end function c_signal
    end interface

contains

    !> Record SIGTERM and SIGINT instead of ending the process (forgets earlier ones).
    subroutine catch_stop_signals()
        type(c_funptr) :: previous

        received = 0
        previous = c_signal(sigterm, c_funloc(on_stop_signal))
        previous = c_signal(sigint, c_funloc(on_stop_signal))
    end subroutine catch_stop_signals

    !> Give SIGTERM and SIGINT their default action again.
    subroutine release_stop_signals()
        type(c_funptr) :: previous

        previous = c_signal(sigterm, c_null_funptr)
        previous = c_signal(sigint, c_null_funptr)
    end subroutine release_stop_signals

    !> The stop signal received since catch_stop_signals (sigterm or sigint), 0 if none.
    integer function stop_signal()
        stop_signal = int(received)
    end function stop_signal

    !> "SIGTERM", "SIGINT" or "signal N".
    function signal_name(signum) result(name)
        integer, intent(in) :: signum
            !! signal number
        character(len=:), allocatable :: name

        character(len=16) :: buf

        select case (signum)
        case (sigterm)
            name = "SIGTERM"
        case (sigint)
            name = "SIGINT"
        case default
            write (buf, "(a,i0)") "signal ", signum
            name = trim(buf)
        end select
    end function signal_name

    !> The handler: note the signal and give both signals their default action (SIG_DFL is a
    !> null pointer), so that a second one, of either kind, is not caught. Only
    !> async-signal-safe work here.
    subroutine on_stop_signal(signum) bind(c)
        integer(c_int), value :: signum
            !! the signal

        type(c_funptr) :: previous

        received = signum
        previous = c_signal(sigterm, c_null_funptr)
        previous = c_signal(sigint, c_null_funptr)
    end subroutine on_stop_signal

end module mpm_signals
