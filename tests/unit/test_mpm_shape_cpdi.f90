!> CPDI1 (mpm_shape_cpdi): for domains turned and stretched by F, near the grid faces and
!> with corners beyond them, the weights sum to one, the gradients to zero, and both
!> reproduce linear fields (sum N_i x_i = x_p, sum x_i (x) grad N_i = I); with F = I the
!> full weights are the tensor product of the 1D weights (`evaluate`, a second code path);
!> a domain inside one cell gives the bilinear hats at the particle, also turned by any
!> angle (the mean of a bilinear function over the corners of a turned square is its value
!> at the centre); a domain stretched across more than the stencil's box, or inverted, is
!> reported; and the per-step stencils (mpm_stencil) keep the full weights and refuse such a
!> particle with its number (exit 3).
program test_mpm_shape_cpdi
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_testing_grid, only: made_up_grid, dims
    use mpm_error, only: error_type, exit_numerical
    use mpm_grid, only: grid_type, node_position
    use mpm_particles, only: particles_type
    use mpm_shape, only: stencil_type
    use mpm_shape_linear, only: linear_shape_type
    use mpm_shape_cpdi, only: cpdi_shape_type
    use mpm_stencil, only: stencils_type, compute_stencils, particle_nodes
    implicit none

    type(test_suite_type) :: suite
    type(cpdi_shape_type) :: cpdi
    real(wp), parameter :: round_off = 200.0_wp*epsilon(1.0_wp)
    real(wp), parameter :: pi = acos(-1.0_wp)

    call new_suite(suite, "mpm_shape_cpdi")
    call check_completeness(2)
    call check_completeness(3)
    call check_aligned(2)
    call check_aligned(3)
    call check_one_cell()
    call check_misfits()
    call check_stencils()
    call finish(suite)

contains

    !> 7 x 6 (x 5) cells of 0.1 m from (1, -2, 0.5).
    subroutine make_grid(grid, dim)
        type(grid_type), intent(out) :: grid
        integer, intent(in) :: dim
        call made_up_grid(grid, dim, [7, 6, 5], 0.1_wp, [1.0_wp, -2.0_wp, 0.5_wp])
    end subroutine make_grid

    !> The node (1-based linear index) of entry (i, j, k) of a box from first.
    pure integer function box_node(grid, first, i, j, k)
        type(grid_type), intent(in) :: grid
        integer, intent(in) :: first(:), i, j, k
        box_node = 1 + first(1) + i - 1 + grid%nn(1)*(first(2) + j - 1)
        if (grid%dim == 3) box_node = box_node + grid%nn(1)*grid%nn(2)*(first(3) + k - 1)
    end function box_node

    !> A deformation gradient: a turn by angle t (about z, then about x in 3D) times a stretch
    !> s1, s2, s3 along the axes and a shear g.
    pure function deformation(dim, t, s, g) result(f)
        integer, intent(in) :: dim
        real(wp), intent(in) :: t, s(3), g
        real(wp) :: f(dim, dim)
        real(wp) :: r(3, 3), u(3, 3), rx(3, 3)
        r = reshape([cos(t), sin(t), 0.0_wp, -sin(t), cos(t), 0.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], &
            [3, 3])
        rx = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, cos(0.7_wp*t), sin(0.7_wp*t), 0.0_wp, &
            -sin(0.7_wp*t), cos(0.7_wp*t)], [3, 3])
        if (dim == 3) r = matmul(rx, r)
        u = 0.0_wp
        u(1, 1) = s(1)
        u(2, 2) = s(2)
        u(3, 3) = s(3)
        u(1, 2) = g
        u = matmul(r, u)
        f = u(1:dim, 1:dim)
    end function deformation

    !> Partition of unity, zero-sum gradients and linear completeness for turned and stretched
    !> domains anywhere in the grid, a share of them on a face with corners beyond it.
    subroutine check_completeness(dim)
        integer, intent(in) :: dim

        type(grid_type) :: grid
        integer, parameter :: n = 3000
        real(wp) :: x(dim, n), f(dim, dim, n), lp0(dim, n), t, s(3), pos(3)
        real(wp), allocatable :: w(:, :), dw(:, :, :)
        integer, allocatable :: first(:, :)
        integer :: p, a, b, nper(3), bad, q, i, j, k, node
        real(wp) :: worst_pu, worst_dw, worst_x, worst_grad, rec(3), grec(3, 3), eye(3, 3)
        logical :: beyond

        call make_grid(grid, dim)
        nper = 1
        nper(1:dim) = 4
        beyond = .false.
        do p = 1, n
            t = 2.0_wp*pi*modulo(0.754877666_wp*p, 1.0_wp)
            s = 0.6_wp + 1.2_wp*[modulo(0.569840291_wp*p, 1.0_wp), &
                modulo(0.362185_wp*p, 1.0_wp), modulo(0.2134_wp*p, 1.0_wp)]
            f(:, :, p) = deformation(dim, t, s, 0.3_wp*modulo(0.1234_wp*p, 1.0_wp))
            lp0(:, p) = 0.2_wp*grid%dx
            do a = 1, dim
                x(a, p) = grid%origin(a) + grid%dx*grid%ncells(a)*modulo(0.6180339887_wp*p &
                    *(a + 1) + 0.31_wp*a, 1.0_wp)
                ! every tenth particle on a face: its turned domain reaches past it
                if (mod(p, 10) == a) x(a, p) = grid%origin(a) + grid%dx*0.05_wp
                if (mod(p, 10) == a + 4) x(a, p) = grid%origin(a) + grid%dx*(grid%ncells(a) - 0.05_wp)
            end do
            do a = 1, dim
                if (x(a, p) - grid%origin(a) < sum(abs(f(a, :, p)))*lp0(1, p)) beyond = .true.
            end do
        end do
        allocate (w(product(nper), n), dw(dim, product(nper), n), first(dim, n))
        call cpdi%weights_full(grid, x, f, lp0, nper, first, w, dw, bad)
        call check(suite, bad == 0, dims(dim)//": every domain fits its box")
        call check(suite, beyond, dims(dim)//": some corners lie beyond a face")
        eye = 0.0_wp
        do a = 1, 3
            eye(a, a) = 1.0_wp
        end do
        worst_pu = 0.0_wp
        worst_dw = 0.0_wp
        worst_x = 0.0_wp
        worst_grad = 0.0_wp
        do p = 1, n
            rec = 0.0_wp
            grec = 0.0_wp
            q = 0
            do k = 1, nper(3)
                do j = 1, nper(2)
                    do i = 1, nper(1)
                        q = q + 1
                        node = box_node(grid, first(:, p), i, j, k)
                        pos = node_position(grid, node)
                        rec(1:dim) = rec(1:dim) + w(q, p)*pos(1:dim)
                        do b = 1, dim
                            grec(1:dim, b) = grec(1:dim, b) + pos(1:dim)*dw(b, q, p)
                        end do
                    end do
                end do
            end do
            worst_pu = max(worst_pu, abs(sum(w(:, p)) - 1.0_wp))
            worst_dw = max(worst_dw, maxval(abs(sum(dw(:, :, p), dim=2)))*grid%dx)
            worst_x = max(worst_x, maxval(abs(rec(1:dim) - x(:, p)))/grid%dx)
            worst_grad = max(worst_grad, maxval(abs(grec(1:dim, 1:dim) - eye(1:dim, 1:dim))))
        end do
        call check(suite, worst_pu <= round_off, dims(dim)//": weights sum to one")
        call check(suite, worst_dw <= round_off, dims(dim)//": gradients sum to zero")
        call check(suite, worst_x <= round_off, dims(dim)//": sum N_i x_i = x_p")
        call check(suite, worst_grad <= round_off, dims(dim)//": sum x_i grad N_i = I")
    end subroutine check_completeness

    !> With F = I, the full weights and gradients of each node equal the tensor product of
    !> the 1D weights (evaluate) for domains inside the grid.
    subroutine check_aligned(dim)
        integer, intent(in) :: dim

        type(grid_type) :: grid
        type(stencil_type) :: st
        integer, parameter :: n = 500
        real(wp) :: x(dim, n), f(dim, dim, n), lp0(dim, n), worst
        real(wp), allocatable :: w(:, :), dw(:, :, :)
        integer, allocatable :: first(:, :)
        integer :: p, a, nper(3), bad, q, i, j, k, node, c
        real(wp) :: wq, dwq(3)

        call make_grid(grid, dim)
        nper = 1
        nper(1:dim) = 4
        f = 0.0_wp
        do p = 1, n
            do a = 1, dim
                f(a, a, p) = 1.0_wp
                lp0(a, p) = grid%dx*(0.15_wp + 0.3_wp*modulo(0.41_wp*p*a, 1.0_wp))
                x(a, p) = grid%origin(a) + lp0(a, p) + (grid%dx*grid%ncells(a) - 2*lp0(a, p)) &
                    *modulo(0.6180339887_wp*p*(a + 1), 1.0_wp)
            end do
        end do
        allocate (w(product(nper), n), dw(dim, product(nper), n), first(dim, n))
        call cpdi%weights_full(grid, x, f, lp0, nper, first, w, dw, bad)
        worst = 0.0_wp
        do p = 1, n
            call cpdi%evaluate(grid, x(:, p), lp0(:, p), st)
            q = 0
            do k = 1, nper(3)
                do j = 1, nper(2)
                    do i = 1, nper(1)
                        q = q + 1
                        node = box_node(grid, first(:, p), i, j, k)
                        wq = 0.0_wp
                        dwq = 0.0_wp
                        do c = 1, st%count
                            if (st%node(c) == node) then
                                wq = st%w(c)
                                dwq = st%dw(:, c)
                            end if
                        end do
                        worst = max(worst, abs(wq - w(q, p)), &
                            maxval(abs(dwq(1:dim) - dw(:, q, p)))*grid%dx)
                    end do
                end do
            end do
        end do
        call check(suite, bad == 0 .and. worst <= round_off, dims(dim)// &
            ": F = I gives the tensor product of the 1D weights")
    end subroutine check_aligned

    !> A square domain inside one cell, turned by any angle: the weights are the bilinear hats
    !> at the particle.
    subroutine check_one_cell()
        type(grid_type) :: grid
        type(stencil_type) :: st
        type(linear_shape_type) :: linear
        integer, parameter :: n = 50
        real(wp) :: x(2, n), f(2, 2, n), lp0(2, n), worst
        real(wp), allocatable :: w(:, :), dw(:, :, :)
        integer, allocatable :: first(:, :)
        integer :: p, nper(3), bad, q, i, j, node, c
        real(wp) :: wq, t

        call make_grid(grid, 2)
        nper = [4, 4, 1]
        do p = 1, n
            t = 2.0_wp*pi*real(p, wp)/real(n, wp)
            f(:, :, p) = deformation(2, t, [1.0_wp, 1.0_wp, 1.0_wp], 0.0_wp)
            lp0(:, p) = 0.1_wp*grid%dx
            ! inside cell (3, 2), at least 0.15 dx from its faces
            x(:, p) = grid%origin(1:2) + grid%dx*([3.0_wp, 2.0_wp] + 0.15_wp &
                + 0.7_wp*[modulo(0.618_wp*p, 1.0_wp), modulo(0.382_wp*p, 1.0_wp)])
        end do
        allocate (w(16, n), dw(2, 16, n), first(2, n))
        call cpdi%weights_full(grid, x, f, lp0, nper, first, w, dw, bad)
        worst = 0.0_wp
        do p = 1, n
            call linear%evaluate(grid, x(:, p), lp0(:, p), st)
            q = 0
            do j = 1, 4
                do i = 1, 4
                    q = q + 1
                    node = box_node(grid, first(:, p), i, j, 1)
                    wq = 0.0_wp
                    do c = 1, st%count
                        if (st%node(c) == node) wq = st%w(c)
                    end do
                    worst = max(worst, abs(wq - w(q, p)))
                end do
            end do
        end do
        call check(suite, bad == 0 .and. worst <= round_off, &
            "2D: a turned square inside a cell takes the bilinear hats at its centre")
    end subroutine check_one_cell

    !> A domain stretched across more than 4 nodes, and an inverted one, are reported.
    subroutine check_misfits()
        type(grid_type) :: grid
        real(wp) :: x(2, 3), f(2, 2, 3), lp0(2, 3), w(16, 3), dw(2, 16, 3)
        integer :: first(2, 3), bad

        call make_grid(grid, 2)
        lp0 = 0.25_wp*grid%dx
        x(:, 1) = grid%origin(1:2) + 3.5_wp*grid%dx
        x(:, 2) = x(:, 1)
        x(:, 3) = x(:, 1)
        f(:, :, 1) = reshape([1.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
        ! stretched 7 times along x: corners 1.75 dx from the centre, in 4 cells
        f(:, :, 2) = reshape([7.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
        f(:, :, 3) = reshape([1.0_wp, 0.0_wp, 0.0_wp, -1.0_wp], [2, 2])
        call cpdi%weights_full(grid, x(:, 1:1), f(:, :, 1:1), lp0(:, 1:1), [4, 4, 1], first(:, 1:1), &
            w(:, 1:1), dw(:, :, 1:1), bad)
        call check(suite, bad == 0, "an undeformed domain fits")
        call cpdi%weights_full(grid, x, f, lp0, [4, 4, 1], first, w, dw, bad)
        call check(suite, bad == 2, "a domain across four cells is reported")
        call cpdi%weights_full(grid, x(:, 3:3), f(:, :, 3:3), lp0(:, 3:3), [4, 4, 1], &
            first(:, 3:3), w(:, 3:3), dw(:, :, 3:3), bad)
        call check(suite, bad == 1, "an inverted domain is reported")
    end subroutine check_misfits

    !> compute_stencils keeps the full weights (particle_nodes gives them back) and refuses a
    !> particle stretched past its box with its number and exit 3.
    subroutine check_stencils()
        type(grid_type) :: grid
        type(particles_type) :: particles
        type(stencils_type) :: stc
        type(error_type), allocatable :: error
        integer, parameter :: n = 200
        integer :: p, a, node(64)
        real(wp) :: w(64), dw(3, 64), worst, sx

        call make_grid(grid, 2)
        particles%n = n
        particles%dim = 2
        allocate (particles%x(2, n), particles%lp0(2, n), &
            particles%f(2, 2, n), particles%id(n))
        do p = 1, n
            do a = 1, 2
                particles%x(a, p) = grid%origin(a) + grid%dx*grid%ncells(a) &
                    *modulo(0.6180339887_wp*p*(a + 1) + 0.1_wp, 1.0_wp)
            end do
            particles%f(:, :, p) = deformation(2, 0.1_wp*p, [1.2_wp, 0.9_wp, 1.0_wp], 0.1_wp)
            particles%id(p) = 1000 + p
        end do
        particles%lp0 = 0.25_wp*grid%dx
        call compute_stencils(stc, grid, particles, cpdi, error)
        call check(suite, .not. allocated(error), "stencils of turned domains computed")
        if (allocated(error)) return
        call check(suite, .not. stc%tensor .and. stc%count == 16, "full stencils of 4 x 4 nodes")
        worst = 0.0_wp
        do p = 1, n
            call particle_nodes(stc, p, node, w, dw)
            sx = 0.0_wp
            do a = 1, stc%count
                sx = sx + w(a)*node_position_x(grid, node(a))
            end do
            worst = max(worst, abs(sum(w(1:stc%count)) - 1.0_wp), abs(sx - particles%x(1, p)) &
                /grid%dx, maxval(abs(sum(dw(1:2, 1:stc%count), dim=2)))*grid%dx)
        end do
        call check(suite, worst <= round_off, "particle_nodes gives the full weights back")
        particles%f(:, :, 7) = reshape([9.0_wp, 0.0_wp, 0.0_wp, 1.0_wp], [2, 2])
        call compute_stencils(stc, grid, particles, cpdi, error)
        call check(suite, allocated(error), "a particle stretched past its box stops the step")
        if (.not. allocated(error)) return
        call check(suite, error%code == exit_numerical .and. index(error%message, "particle 1007") &
            > 0 .and. index(error%message, "CPDI") > 0, "with exit 3 and the particle: "// &
            error%message)
    end subroutine check_stencils

    real(wp) function node_position_x(grid, node)
        type(grid_type), intent(in) :: grid
        integer, intent(in) :: node
        real(wp) :: pos(3)
        pos = node_position(grid, node)
        node_position_x = pos(1)
    end function node_position_x

end program test_mpm_shape_cpdi
