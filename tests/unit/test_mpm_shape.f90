!> Shape functions: partition of unity, zero-sum gradients, linear completeness, gradients
!> against finite differences, and the piecewise cpGIMP values at chosen points, for every
!> shape function of the registry (the B-splines and uGIMP in test_mpm_shape_spline too).
program test_mpm_shape
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_testing_grid, only: made_up_grid, dims
    use mpm_grid, only: grid_type, node_position
    use mpm_shape, only: shape_type, stencil_type
    use mpm_shape_linear, only: linear_shape_type
    use mpm_shape_gimp, only: gimp_shape_type, gimp_weight
    use mpm_shape_ugimp, only: ugimp_shape_type
    use mpm_shape_bspline2, only: bspline2_shape_type
    use mpm_shape_bspline3, only: bspline3_shape_type
    implicit none

    type(test_suite_type) :: suite
    type(linear_shape_type) :: linear
    type(gimp_shape_type) :: gimp
    type(ugimp_shape_type) :: ugimp
    type(bspline2_shape_type) :: bspline2
    type(bspline3_shape_type) :: bspline3
    real(wp), parameter :: round_off = 100.0_wp*epsilon(1.0_wp)

    call new_suite(suite, "mpm_shape")
    call check_piecewise_values()
    call check_shape(linear, "linear", 2)
    call check_shape(linear, "linear", 3)
    call check_shape(gimp, "cpgimp", 2)
    call check_shape(gimp, "cpgimp", 3)
    call check_shape(ugimp, "ugimp", 2)
    call check_shape(ugimp, "ugimp", 3)
    call check_shape(bspline2, "bspline2", 2)
    call check_shape(bspline2, "bspline2", 3)
    call check_shape(bspline3, "bspline3", 2)
    call check_shape(bspline3, "bspline3", 3)
    call finish(suite)

contains

    !> Values of the 1D cpGIMP pieces at chosen points (L = 1, lp = 1/4), by hand:
    !> S(0) = 1 - lp/(2L) = 0.875, S(0.2) = 1 - (0.04 + 0.0625)/0.5 = 0.795,
    !> S(0.5) = 0.5, S(1) = (1.25 - 1)**2 / 1 = 0.0625, S(1.25) = 0.
    subroutine check_piecewise_values()
        real(wp) :: s, ds, sl, dsl, sr, dsr
        real(wp), parameter :: lp = 0.25_wp, dx = 1.0_wp
        real(wp), parameter :: r(6) = [0.0_wp, 0.2_wp, 0.5_wp, -0.5_wp, 1.0_wp, 1.25_wp]
        real(wp), parameter :: expected_s(6) = [0.875_wp, 0.795_wp, 0.5_wp, 0.5_wp, &
            0.0625_wp, 0.0_wp]
        real(wp), parameter :: expected_ds(6) = [0.0_wp, -0.8_wp, -1.0_wp, 1.0_wp, -0.5_wp, &
            0.0_wp]
        real(wp), parameter :: breaks(2) = [lp, dx - lp]
        integer :: i
        character(len=40) :: what

        do i = 1, size(r)
            call gimp_weight(r(i), lp, dx, s, ds)
            write (what, "(a,f6.3)") "cpGIMP S at r =", r(i)
            call check_close(suite, s, expected_s(i), round_off, trim(what))
            write (what, "(a,f6.3)") "cpGIMP dS/dx at r =", r(i)
            call check_close(suite, ds, expected_ds(i), round_off, trim(what))
        end do
        ! continuity of S and dS at the breakpoints |r| = lp and |r| = L - lp
        do i = 1, 2
            call gimp_weight(breaks(i) - 1.0e-10_wp, lp, dx, sl, dsl)
            call gimp_weight(breaks(i) + 1.0e-10_wp, lp, dx, sr, dsr)
            call check_close(suite, sl, sr, 1.0e-9_wp, "cpGIMP S continuous at a breakpoint")
            call check_close(suite, dsl, dsr, 1.0e-9_wp, "cpGIMP dS continuous at a breakpoint")
        end do
    end subroutine check_piecewise_values

    !> Partition of unity, zero-sum gradients, linear completeness and finite-difference
    !> gradients at particle positions inside cells, near the domain faces and straddling
    !> cell faces.
    subroutine check_shape(shape, name, dim)
        class(shape_type), intent(in) :: shape
        character(len=*), intent(in) :: name
        integer, intent(in) :: dim

        type(grid_type) :: grid
        type(stencil_type) :: st, stp, stm
        real(wp) :: xp(3), lp(3), pos(3), sumw, sumdw(3), xrec(3), h, fd
        real(wp) :: worst_pu, worst_dw, worst_lin, worst_fd
        integer :: trial, c, a, k, ntrial
        real(wp) :: base(3)

        call made_up_grid(grid, dim, [6, 5, 4], 0.1_wp, [1.0_wp, -2.0_wp, 0.5_wp])
        lp = 0.25_wp*grid%dx   ! 2 particles per cell
        worst_pu = 0.0_wp
        worst_dw = 0.0_wp
        worst_lin = 0.0_wp
        worst_fd = 0.0_wp
        ntrial = 400
        do trial = 1, ntrial
            ! positions: a quasi-random sweep of the interior, plus special places
            do a = 1, 3
                base(a) = modulo(0.618034_wp*real(trial*(a + 2), wp) + 0.1_wp*a, 1.0_wp)
            end do
            select case (mod(trial, 4))
            case (0) ! anywhere in an interior cell
                xp = grid%origin + grid%dx*(2.0_wp + base)
            case (1) ! straddling a cell face: within lp of a node plane
                xp = grid%origin + grid%dx*(3.0_wp + (base - 0.5_wp)*0.4_wp)
            case (2) ! near the lower domain faces, the particle domain inside the domain
                xp = grid%origin + lp + (grid%dx - 2.0_wp*lp)*base
            case (3) ! near the upper domain faces
                xp = grid%origin + grid%dx*real(grid%ncells, wp) - lp - (grid%dx - 2.0_wp*lp)*base
            end select
            call shape%evaluate(grid, xp(1:dim), lp(1:dim), st)
            sumw = sum(st%w(1:st%count))
            sumdw = sum(st%dw(:, 1:st%count), dim=2)
            xrec = 0.0_wp
            do c = 1, st%count
                pos = node_position(grid, st%node(c))
                xrec = xrec + st%w(c)*pos
            end do
            worst_pu = max(worst_pu, abs(sumw - 1.0_wp))
            worst_dw = max(worst_dw, maxval(abs(sumdw(1:dim)))*grid%dx)
            worst_lin = max(worst_lin, maxval(abs(xrec(1:dim) - xp(1:dim)))/grid%dx)
            ! central finite differences of each weight, away from the kinks of the hat
            h = 1.0e-7_wp*grid%dx
            ! (the splines are C1 everywhere: also straddling a cell face and at the domain
            ! faces, where the boundary modification acts)
            if ((mod(trial, 4) == 0 .and. name /= "linear") .or. index(name, "bspline") == 1) &
                then
                do a = 1, dim
                    pos = xp
                    pos(a) = xp(a) + h
                    call shape%evaluate(grid, pos(1:dim), lp(1:dim), stp)
                    pos(a) = xp(a) - h
                    call shape%evaluate(grid, pos(1:dim), lp(1:dim), stm)
                    do c = 1, st%count
                        fd = (weight_of(stp, st%node(c)) - weight_of(stm, st%node(c)))/(2*h)
                        worst_fd = max(worst_fd, abs(fd - st%dw(a, c))*grid%dx)
                    end do
                end do
            end if
            k = st%count
        end do
        call check(suite, worst_pu <= round_off, name//" partition of unity ("//dims(dim)//")")
        call check(suite, worst_dw <= round_off, name//" gradients sum to zero ("//dims(dim)//")")
        call check(suite, worst_lin <= round_off, name//" reproduces x linearly ("//dims(dim)//")")
        if (name /= "linear") then
            ! central differences: truncation ~ h^2 S''' (S'' jumps only at breakpoints) and
            ! round-off ~ eps / h relative to dx: 1e-6 is ample and still tight
            call check(suite, worst_fd <= 1.0e-6_wp, name//" gradient matches finite "// &
                "differences ("//dims(dim)//")")
        end if
        call check(suite, k >= 1, name//" stencil not empty")
    end subroutine check_shape

    real(wp) function weight_of(st, node)
        type(stencil_type), intent(in) :: st
        integer, intent(in) :: node
        integer :: c
        weight_of = 0.0_wp
        do c = 1, st%count
            if (st%node(c) == node) weight_of = st%w(c)
        end do
    end function weight_of

end program test_mpm_shape
