!> Kind parameters used everywhere in mpm-geo.
module mpm_kinds
    implicit none
    private
    public :: wp, i8

    integer, parameter :: wp = selected_real_kind(15)
        !! working precision for every real (IEEE double)
    integer, parameter :: i8 = selected_int_kind(18)
        !! 64-bit integers for counters that can pass 2**31 (particle-steps)
end module mpm_kinds
