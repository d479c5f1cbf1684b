!> Verification: the 1D large-deformation manufactured solution (REFERENCES.md section 3),
!> A = 0.05 (strains up to 30 %), one period, CFL 0.2, 2 particles per cell.
!>
!> Expected physics, checked rather than assumed:
!> - cpGIMP converges at about second order while the spatial error dominates: the observed
!>   order between 16 and 32 cells is at least 1.5 (USL and MUSL), and the L2 error at 32
!>   cells is below 1e-4 m (0.2 % of A);
!> - linear shape functions lose convergence under this deformation (cell crossing): halving
!>   the cells from 16 to 32 does not even halve their error.
program test_manufactured
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_error, only: error_type
    use mpm_manufactured, only: mms_result_type, run_manufactured
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "manufactured")
    call gimp_order("MUSL")
    call gimp_order("USL")
    call linear_stalls()
    call finish(suite)

contains

    subroutine gimp_order(scheme)
        character(len=*), intent(in) :: scheme

        type(mms_result_type) :: coarse, fine
        type(error_type), allocatable :: error
        real(wp) :: order

        call run_manufactured(16, "cpgimp", scheme, 0.05_wp, 0.02_wp, 0.2_wp, 2, coarse, error)
        call check(suite, .not. allocated(error), "cpgimp "//scheme//": 16 cells run")
        if (allocated(error)) return
        call run_manufactured(32, "cpgimp", scheme, 0.05_wp, 0.02_wp, 0.2_wp, 2, fine, error)
        call check(suite, .not. allocated(error), "cpgimp "//scheme//": 32 cells run")
        if (allocated(error)) return
        order = log(coarse%error_l2/fine%error_l2)/log(2.0_wp)
        call check(suite, order >= 1.5_wp, "cpgimp "//scheme//": observed order >= 1.5")
        call check(suite, fine%error_l2 < 1.0e-4_wp, "cpgimp "//scheme// &
            ": L2 error at 32 cells below 1e-4 m")
        print "(a,a,3(a,es10.3))", "cpgimp ", scheme, ": L2 error 16 cells ", coarse%error_l2, &
            ", 32 cells ", fine%error_l2, ", order ", order
    end subroutine gimp_order

    subroutine linear_stalls()
        type(mms_result_type) :: coarse, fine
        type(error_type), allocatable :: error

        call run_manufactured(16, "linear", "MUSL", 0.05_wp, 0.02_wp, 0.2_wp, 2, coarse, error)
        if (.not. allocated(error)) then
            call run_manufactured(32, "linear", "MUSL", 0.05_wp, 0.02_wp, 0.2_wp, 2, fine, error)
        end if
        call check(suite, .not. allocated(error), "linear MUSL: 16 and 32 cells run")
        if (allocated(error)) return
        call check(suite, fine%error_l2 > 0.5_wp*coarse%error_l2, &
            "linear MUSL: no convergence under large deformation (cell crossing)")
        print "(a,2(a,es10.3))", "linear MUSL", ": L2 error 16 cells ", coarse%error_l2, &
            ", 32 cells ", fine%error_l2
    end subroutine linear_stalls

end program test_manufactured
