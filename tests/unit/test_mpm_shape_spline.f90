!> The B-spline and uGIMP shape functions beyond test_mpm_shape: values by hand, the
!> smoothness of the splines (C1 quadratic, C2 cubic) at their knots and at the end of the
!> boundary modification, mirror symmetry, non-negative weights, linear reproduction up to the
!> grid ends, grids of one and two cells, the stencils of uGIMP on the initial domain, and
!> the registry (every name, any letter case; an unknown name refused with exit 2).
program test_mpm_shape_spline
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, exit_input
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, check_contains, &
        finish
    use mpm_grid, only: grid_type
    use mpm_particles, only: particles_type
    use mpm_shape, only: shape_type, shape_name_width
    use mpm_shape_gimp, only: gimp_shape_type
    use mpm_shape_ugimp, only: ugimp_shape_type
    use mpm_shape_bspline2, only: bspline2_shape_type, bspline2_weights_1d
    use mpm_shape_bspline3, only: bspline3_shape_type, bspline3_weights_1d
    use mpm_shape_factory, only: new_shape, shape_choices
    use mpm_stencil, only: stencils_type, compute_stencils
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: round_off = 100.0_wp*epsilon(1.0_wp)

    call new_suite(suite, "mpm_shape_spline")
    call check_values()
    call check_smoothness(2, 8)
    call check_smoothness(3, 8)
    call check_symmetry_and_sign(2)
    call check_symmetry_and_sign(3)
    call check_small_grids(2)
    call check_small_grids(3)
    call check_ugimp_domain()
    call check_registry()
    call finish(suite)

contains

    !> 1D weights of either spline (degree 2 or 3) at xi on a grid of ncells cells (dx = 1),
    !> as values of nodes 0 .. ncells.
    subroutine node_weights(degree, xi, ncells, w, dw)
        integer, intent(in) :: degree, ncells
        real(wp), intent(in) :: xi
        real(wp), intent(out) :: w(0:ncells), dw(0:ncells)

        integer :: first, k
        real(wp) :: w4(4), dw4(4)

        w4 = 0.0_wp
        dw4 = 0.0_wp
        if (degree == 2) then
            call bspline2_weights_1d(xi, 1.0_wp, ncells, first, w4(1:3), dw4(1:3))
        else
            call bspline3_weights_1d(xi, 1.0_wp, ncells, first, w4, dw4)
        end if
        w = 0.0_wp
        dw = 0.0_wp
        do k = 1, degree + 1
            if (first + k - 1 >= 0 .and. first + k - 1 <= ncells) then
                w(first + k - 1) = w4(k)
                dw(first + k - 1) = dw4(k)
            else
                ! a node outside the grid keeps nothing (folded into the grid's end nodes)
                call check(suite, w4(k) == 0.0_wp .and. dw4(k) == 0.0_wp, &
                    "a node outside the grid has zero weight and derivative")
            end if
        end do
    end subroutine node_weights

    !> Values by hand (dx = 1): the quadratic spline on a node is 3/4 and 1/8 on its
    !> neighbours, the cubic 2/3 and 1/6; at a grid end the end node has weight 1; within
    !> half a cell of it the modified quadratic splines are 1 - x and x, the cubic
    !> end spline 1 - x + x**3/6 within a cell.
    subroutine check_values()
        real(wp) :: w(0:8), dw(0:8)

        call node_weights(2, 4.0_wp, 8, w, dw)
        call check(suite, abs(w(4) - 0.75_wp) <= round_off .and. abs(w(3) - 0.125_wp) <= &
            round_off .and. abs(w(5) - 0.125_wp) <= round_off, "quadratic: 1/8, 3/4, 1/8 on a node")
        call check_close(suite, dw(4), 0.0_wp, round_off, "quadratic: zero slope on its node")
        call node_weights(3, 4.0_wp, 8, w, dw)
        call check(suite, abs(w(4) - 2.0_wp/3.0_wp) <= round_off .and. abs(w(3) - 1.0_wp/6.0_wp) <= &
            round_off .and. abs(w(5) - 1.0_wp/6.0_wp) <= round_off .and. w(2) == 0.0_wp, &
            "cubic: 1/6, 2/3, 1/6 on a node")
        call check_close(suite, dw(3), -0.5_wp, round_off, "cubic: slope -1/2 one cell behind")
        call node_weights(2, 0.0_wp, 8, w, dw)
        call check_close(suite, w(0), 1.0_wp, round_off, "quadratic: weight 1 at the lower end")
        call node_weights(2, 8.0_wp, 8, w, dw)
        call check_close(suite, w(8), 1.0_wp, round_off, "quadratic: weight 1 at the upper end")
        call node_weights(3, 0.0_wp, 8, w, dw)
        call check_close(suite, w(0), 1.0_wp, round_off, "cubic: weight 1 at the lower end")
        call node_weights(3, 8.0_wp, 8, w, dw)
        call check_close(suite, w(8), 1.0_wp, round_off, "cubic: weight 1 at the upper end")
        call node_weights(2, 0.3_wp, 8, w, dw)
        call check(suite, abs(w(0) - 0.7_wp) <= round_off .and. abs(w(1) - 0.3_wp) <= round_off &
            .and. abs(dw(0) + 1.0_wp) <= round_off .and. abs(dw(1) - 1.0_wp) <= round_off, &
            "quadratic: 1 - x and x within half a cell of the end")
        call node_weights(3, 0.4_wp, 8, w, dw)
        call check_close(suite, w(0), 1.0_wp - 0.4_wp + 0.4_wp**3/6.0_wp, round_off, &
            "cubic: 1 - x + x**3/6 at the end node")
    end subroutine check_values

    !> Along a grid of n cells, every node's weight is continuous, so is its derivative
    !> (C1) and, for the cubic, its second derivative (C2, from central differences of the
    !> derivative), at every knot (cell midpoints quadratic, nodes cubic) and where the
    !> boundary modification ends; the derivatives match central differences of the weights.
    subroutine check_smoothness(degree, n)
        integer, intent(in) :: degree, n

        real(wp), parameter :: e = 1.0e-7_wp, h = 1.0e-4_wp
        real(wp) :: wl(0:n), wr(0:n), dwl(0:n), dwr(0:n), wp_(0:n), wm(0:n), dwp(0:n), &
            dwm(0:n), w(0:n), dw(0:n), x, jump_w, jump_dw, jump_ddw, worst_fd
        real(wp), allocatable :: knots(:)
        integer :: k, i
        character(len=:), allocatable :: what

        what = merge("quadratic", "cubic    ", degree == 2)
        if (degree == 2) then
            knots = [(real(k, wp) + 0.5_wp, k=0, n - 1)]
        else
            knots = [(real(k, wp), k=1, n - 1)]
        end if
        jump_w = 0.0_wp
        jump_dw = 0.0_wp
        jump_ddw = 0.0_wp
        do k = 1, size(knots)
            call node_weights(degree, knots(k) - e, n, wl, dwl)
            call node_weights(degree, knots(k) + e, n, wr, dwr)
            jump_w = max(jump_w, maxval(abs(wr - wl)))
            jump_dw = max(jump_dw, maxval(abs(dwr - dwl)))
            if (degree == 3) then
                ! one-sided second derivatives on either side of the knot
                call node_weights(degree, knots(k) - h, n, wm, dwm)
                call node_weights(degree, knots(k) + h, n, wp_, dwp)
                jump_ddw = max(jump_ddw, maxval(abs((dwp - dwr)/(h - e) - (dwl - dwm)/(h - e))))
            end if
        end do
        ! weights move by about |dw| 2e, derivatives by about |ddw| 2e (2e = 2e-7)
        call check(suite, jump_w <= 1.0e-6_wp, trim(what)//": weights continuous at the knots")
        call check(suite, jump_dw <= 1.0e-5_wp, trim(what)//": derivatives continuous at the "// &
            "knots (C1)")
        if (degree == 3) call check(suite, jump_ddw <= 1.0e-3_wp, trim(what)//": second "// &
            "derivatives continuous at the knots (C2)")
        ! derivatives against central differences, everywhere along the grid
        worst_fd = 0.0_wp
        do i = 1, 997
            x = real(n, wp)*(real(i, wp) + 0.1234_wp)/1000.0_wp
            call node_weights(degree, x, n, w, dw)
            call node_weights(degree, x + h, n, wp_, dwp)
            call node_weights(degree, x - h, n, wm, dwm)
            worst_fd = max(worst_fd, maxval(abs((wp_ - wm)/(2.0_wp*h) - dw)))
        end do
        ! truncation h**2 N''' / 6 with |N'''| <= 2 (quadratic: a jump of N'' across a knot
        ! inside [x - h, x + h] gives at most h |jump| / 4 = 5e-5)
        call check(suite, worst_fd <= 1.0e-4_wp, trim(what)//": derivatives match finite "// &
            "differences along the grid")
    end subroutine check_smoothness

    !> The weights at the mirror image x -> n - x are those of the mirrored nodes, the
    !> derivatives change sign; every weight is non-negative; the weights sum to one,
    !> the derivatives to zero and sum_i N_i x_i = x, up to the grid ends.
    subroutine check_symmetry_and_sign(degree)
        integer, intent(in) :: degree

        integer, parameter :: n = 7
        real(wp) :: w(0:n), dw(0:n), wm(0:n), dwm(0:n), x, worst_sym, worst_pu, worst_dw, &
            worst_lin, lowest
        integer :: i, k
        character(len=:), allocatable :: what

        what = trim(merge("quadratic", "cubic    ", degree == 2))
        worst_sym = 0.0_wp
        worst_pu = 0.0_wp
        worst_dw = 0.0_wp
        worst_lin = 0.0_wp
        lowest = 1.0_wp
        do i = 0, 700
            x = real(n, wp)*real(i, wp)/700.0_wp
            call node_weights(degree, x, n, w, dw)
            call node_weights(degree, real(n, wp) - x, n, wm, dwm)
            do k = 0, n
                worst_sym = max(worst_sym, abs(w(k) - wm(n - k)), abs(dw(k) + dwm(n - k)))
            end do
            worst_pu = max(worst_pu, abs(sum(w) - 1.0_wp))
            worst_dw = max(worst_dw, abs(sum(dw)))
            worst_lin = max(worst_lin, abs(sum(w*[(real(k, wp), k=0, n)]) - x))
            lowest = min(lowest, minval(w))
        end do
        call check(suite, worst_sym <= 10.0_wp*round_off, what//": mirror symmetric")
        call check(suite, lowest >= 0.0_wp, what//": no negative weight")
        call check(suite, worst_pu <= round_off, what//": weights sum to one up to the ends")
        call check(suite, worst_dw <= round_off, what//": derivatives sum to zero up to the ends")
        call check(suite, worst_lin <= 10.0_wp*round_off, what//": sum N_i x_i = x up to the ends")
    end subroutine check_symmetry_and_sign

    !> Grids of one and two cells: every ghost node folded (both ends at once for the cubic
    !> on one cell, which then becomes the linear hat 1 - x, x).
    subroutine check_small_grids(degree)
        integer, intent(in) :: degree

        real(wp) :: w1(0:1), dw1(0:1), w2(0:2), dw2(0:2), x, worst1, worst2
        integer :: i
        character(len=:), allocatable :: what

        what = trim(merge("quadratic", "cubic    ", degree == 2))
        worst1 = 0.0_wp
        worst2 = 0.0_wp
        do i = 0, 100
            x = real(i, wp)/100.0_wp
            call node_weights(degree, x, 1, w1, dw1)
            worst1 = max(worst1, abs(sum(w1) - 1.0_wp), abs(w1(1)*1.0_wp - x), abs(sum(dw1)))
            call node_weights(degree, 2.0_wp*x, 2, w2, dw2)
            worst2 = max(worst2, abs(sum(w2) - 1.0_wp), abs(w2(1) + 2.0_wp*w2(2) - 2.0_wp*x), &
                abs(sum(dw2)))
            if (minval(w1) < 0.0_wp .or. minval(w2) < 0.0_wp) worst2 = huge(1.0_wp)
        end do
        call check(suite, worst1 <= round_off, what//": one cell: the linear hat")
        call check(suite, worst2 <= 10.0_wp*round_off, what//": two cells: unity, linear, "// &
            "non-negative")
    end subroutine check_small_grids

    !> uGIMP's stencils take the initial domain: with lp = lp0 / 2 they are cpGIMP's for
    !> lp = lp0, bit for bit, and differ from cpGIMP's for lp.
    subroutine check_ugimp_domain()
        type(grid_type) :: grid
        type(particles_type) :: shrunk, initial
        type(stencils_type) :: su, sg, sd
        type(ugimp_shape_type) :: ugimp
        type(gimp_shape_type) :: gimp
        type(error_type), allocatable :: error
        integer :: p, n

        grid%dim = 2
        grid%ncells = 1
        grid%ncells(1:2) = [6, 5]
        grid%nn = 1
        grid%nn(1:2) = grid%ncells(1:2) + 1
        grid%nnodes = product(grid%nn)
        grid%dx = 0.1_wp
        grid%origin = [1.0_wp, -2.0_wp, 0.5_wp]
        n = 50
        shrunk%n = n
        shrunk%dim = 2
        allocate (shrunk%x(2, n), shrunk%lp0(2, n), shrunk%f(2, 2, n))
        do p = 1, n
            shrunk%x(1, p) = grid%origin(1) + 0.05_wp + 0.5_wp*modulo(0.618_wp*p, 1.0_wp)
            shrunk%x(2, p) = grid%origin(2) + 0.05_wp + 0.4_wp*modulo(0.414_wp*p, 1.0_wp)
        end do
        shrunk%lp0 = 0.25_wp*grid%dx
        ! F = I / 2: the deformed domain is half the initial one (lp = lp0/2)
        shrunk%f = 0.0_wp
        shrunk%f(1, 1, :) = 0.5_wp
        shrunk%f(2, 2, :) = 0.5_wp
        initial = shrunk
        initial%f(1, 1, :) = 1.0_wp
        initial%f(2, 2, :) = 1.0_wp
        call check(suite, ugimp%initial_domain() .and. .not. gimp%initial_domain(), &
            "uGIMP takes the initial domain, cpGIMP the deformed one")
        call compute_stencils(su, grid, shrunk, ugimp, error)
        if (.not. allocated(error)) call compute_stencils(sg, grid, initial, gimp, error)
        if (.not. allocated(error)) call compute_stencils(sd, grid, shrunk, gimp, error)
        call check(suite, .not. allocated(error), "uGIMP stencils computed")
        if (allocated(error)) return
        call check(suite, all(su%w == sg%w) .and. all(su%dw == sg%dw) .and. &
            all(su%first == sg%first), "uGIMP with lp = lp0/2: cpGIMP's weights of lp0")
        call check(suite, any(su%w /= sd%w), "uGIMP differs from cpGIMP of the shrunk domain")
    end subroutine check_ugimp_domain

    !> Every name of the registry makes a shape of that name, in any letter case; widths;
    !> an unknown name is an input error naming the file, the key and the names allowed.
    subroutine check_registry()
        class(shape_type), allocatable :: shape
        type(error_type), allocatable :: error
        character(len=shape_name_width), allocatable :: choices(:)
        character(len=shape_name_width), allocatable :: names(:)
        integer :: k
        logical :: all_ok

        choices = shape_choices()
        all_ok = size(choices) >= 6
        do k = 1, size(choices)
            call new_shape(shape, trim(choices(k)), error, "case.json")
            if (allocated(error)) then
                all_ok = .false.
                cycle
            end if
            call shape%names(names)
            if (.not. any(names == choices(k))) all_ok = .false.
        end do
        call check(suite, all_ok, "registry: every name makes its shape function")
        call new_shape(shape, "BSpline3", error, "case.json")
        call check(suite, .not. allocated(error), "registry: any letter case")
        if (.not. allocated(error)) call check(suite, shape%nodes_per_axis() == 4 .and. &
            shape%halo_width() == 3, "registry: cubic B-spline, 4 nodes per axis, halo 3")
        call new_shape(shape, "quadratic_bspline", error, "case.json")
        if (.not. allocated(error)) call check(suite, shape%nodes_per_axis() == 3, &
            "registry: quadratic B-spline, 3 nodes per axis")
        call new_shape(shape, "bspline4", error, "case.json")
        call check(suite, allocated(error), "registry: unknown name refused")
        if (.not. allocated(error)) return
        call check(suite, error%code == exit_input, "registry: unknown name is exit 2")
        call check_contains(suite, error%message, 'case.json: solver.shape_function = "bspline4"', &
            "registry: message names file, key and value")
        call check_contains(suite, error%message, '"linear", "cpgimp", "gimp", "ugimp", ' &
            //'"bspline2", "quadratic_bspline", "bspline3", "cubic_bspline"', &
            "registry: message lists the names")
    end subroutine check_registry

end program test_mpm_shape_spline
