!> Wall-clock time for progress lines, summaries and benchmarks.
module mpm_clock
    use mpm_kinds, only: wp, i8
    implicit none
    private
    public :: wall_time

contains

    !> Seconds since an arbitrary fixed point (monotonic) [s].
    real(wp) function wall_time()
        integer(i8) :: count, rate

        call system_clock(count, rate)
        wall_time = real(count, wp)/real(max(rate, 1_i8), wp)
    end function wall_time

end module mpm_clock
