!> Unit tests of the light-node kernel (mpm_kernel_light, through mpm_halo's
!> settle_light_nodes, fold_light and slave_light, which call it on a grid that is not cut)
!> on a 2D grid of 4 x 3 cells with
!> masses set by hand: which nodes are light, their masters and coefficients (the masses of
!> the heavy neighbours in the 3 x 3 box, normalised), the fold of mass and momentum into the
!> masters (totals kept), the slaved velocity (the masters' mass-weighted mean), a held
!> component, and a light node without a heavy neighbour (left alone).
program test_mpm_kernel_light
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_case, only: case_type
    use mpm_grid, only: grid_type, new_grid, node_index
    use mpm_kernel_light, only: find_light_nodes
    use mpm_halo, only: settle_light_nodes, fold_light, slave_light
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: tol = 1.0e-14_wp

    call new_suite(suite, "mpm_kernel_light")
    call test_light_nodes()
    call test_alone()
    call finish(suite)

contains

    !> A grid of 4 x 3 cells of 0.5 m, every face free, nodes light below `light` kg.
    subroutine small_grid(grid, light)
        type(grid_type), intent(out) :: grid
        real(wp), intent(in) :: light

        type(case_type) :: case
        type(error_type), allocatable :: error

        case%dim = 2
        case%domain%ncells = [4, 3, 1]
        case%domain%dx = 0.5_wp
        call new_grid(grid, case, error)
        call check(suite, .not. allocated(error), "new_grid")
        call check(suite, all(grid%active_hi(1:2) < grid%active_lo(1:2)), &
            "new_grid: no node holds anything yet (an empty box)")
        grid%light_mass = light
        ! the tests set nodal masses by hand: the box of the P2G that would have made them
        grid%active_lo = 0
        grid%active_hi = grid%nn - 1
    end subroutine small_grid

    !> Node (2, 1) light beside the heavy nodes (1, 1) of 3 kg and (2, 2) of 1 kg; node
    !> (0, 0) light beside the heavy (1, 1) only.
    subroutine test_light_nodes()
        type(grid_type) :: grid
        integer :: l, h1, h2, c, k, n
        real(wp) :: mass0, momentum0(2), v(2)

        call small_grid(grid, 0.01_wp)
        l = node_index(grid, [2, 1, 0])
        h1 = node_index(grid, [1, 1, 0])
        h2 = node_index(grid, [2, 2, 0])
        c = node_index(grid, [0, 0, 0])
        grid%mass(h1) = 3.0_wp
        grid%mass(h2) = 1.0_wp
        grid%mass(l) = 0.004_wp
        grid%mass(c) = 0.002_wp
        grid%momentum(:, h1) = [3.0_wp, 0.0_wp]
        grid%momentum(:, h2) = [0.0_wp, -1.0_wp]
        grid%momentum(:, l) = [0.008_wp, 0.004_wp]
        grid%momentum(:, c) = [-0.002_wp, 0.0_wp]
        mass0 = sum(grid%mass)
        momentum0 = sum(grid%momentum, dim=2)
        ! the kernel finds them and leaves the masses as they are
        call find_light_nodes(grid, 1)
        call check(suite, grid%nlight == 2 .and. grid%mass(l) == 0.004_wp, &
            "find_light_nodes: two light nodes, no fold yet")
        call settle_light_nodes(grid, 1)
        call check(suite, grid%nlight == 2, "two light nodes")
        if (grid%nlight /= 2) return
        ! in node order: (0, 0) before (2, 1)
        call check(suite, grid%light_node(1) == c .and. grid%light_node(2) == l, &
            "the light nodes in node order")
        n = 2
        call check(suite, grid%light_start(n + 1) - grid%light_start(n) == 2, &
            "node (2, 1): two masters")
        do k = grid%light_start(n), grid%light_start(n + 1) - 1
            if (grid%light_master(k) == h1) then
                call check_close(suite, grid%light_coef(k), 0.75_wp, tol, &
                    "node (2, 1): c = 3 / 4 for the node of 3 kg")
            else
                call check(suite, grid%light_master(k) == h2, "node (2, 1): the other master")
                call check_close(suite, grid%light_coef(k), 0.25_wp, tol, &
                    "node (2, 1): c = 1 / 4 for the node of 1 kg")
            end if
        end do
        call check(suite, grid%light_start(2) - grid%light_start(1) == 1 .and. &
            grid%light_master(grid%light_start(1)) == h1, "node (0, 0): its one master")
        ! the folds: the light nodes keep nothing, the totals stay
        call check(suite, grid%mass(l) == 0.0_wp .and. grid%mass(c) == 0.0_wp .and. &
            all(grid%momentum(:, l) == 0.0_wp), "the light nodes keep no mass or momentum")
        call check_close(suite, sum(grid%mass), mass0, tol, "total mass kept")
        call check_close(suite, grid%mass(h1), 3.0_wp + 0.75_wp*0.004_wp + 0.002_wp, tol, &
            "node (1, 1): its mass + 3/4 of (2, 1)'s + all of (0, 0)'s")
        call check_close(suite, grid%mass(h2), 1.0_wp + 0.25_wp*0.004_wp, tol, &
            "node (2, 2): its mass + 1/4 of (2, 1)'s")
        call check(suite, all(abs(sum(grid%momentum, dim=2) - momentum0) < tol), &
            "total momentum kept")
        ! slaved: v_l = 3/4 v_h1 + 1/4 v_h2
        grid%velocity = 0.0_wp
        grid%velocity(:, h1) = [1.0_wp, 2.0_wp]
        grid%velocity(:, h2) = [-3.0_wp, 4.0_wp]
        call slave_light(grid, grid%velocity)
        v = 0.75_wp*[1.0_wp, 2.0_wp] + 0.25_wp*[-3.0_wp, 4.0_wp]
        call check(suite, all(abs(grid%velocity(:, l) - v) < tol), &
            "node (2, 1): the masters' mass-weighted velocity")
        call check(suite, all(abs(grid%velocity(:, c) - [1.0_wp, 2.0_wp]) < tol), &
            "node (0, 0): its master's velocity")
        ! a held component stays at rest, and its force is not folded
        grid%constrained(2, l) = .true.
        call slave_light(grid, grid%velocity)
        call check(suite, grid%velocity(2, l) == 0.0_wp .and. abs(grid%velocity(1, l) - v(1)) &
            < tol, "a held component of a light node stays at rest")
        grid%momentum(:, l) = [1.0_wp, 1.0_wp]
        grid%momentum(:, h1) = 0.0_wp
        grid%momentum(:, h2) = 0.0_wp
        call fold_light(grid, grid%momentum)
        call check(suite, abs(grid%momentum(1, h1) - 0.75_wp) < tol .and. &
            grid%momentum(2, h1) == 0.0_wp .and. grid%momentum(2, h2) == 0.0_wp, &
            "fold: the free component to the masters, the held one to the support")
        call fold_light(grid, grid%momentum)
        call check(suite, abs(grid%momentum(1, h1) - 0.75_wp) < tol, &
            "fold: a second call adds nothing")
    end subroutine test_light_nodes

    !> Light nodes with no heavy neighbour keep their mass; no threshold, no light node.
    subroutine test_alone()
        type(grid_type) :: grid
        integer :: a, b

        call small_grid(grid, 0.01_wp)
        a = node_index(grid, [1, 1, 0])
        b = node_index(grid, [2, 1, 0])
        grid%mass(a) = 0.005_wp
        grid%mass(b) = 0.001_wp
        call settle_light_nodes(grid, 1)
        call check(suite, grid%nlight == 0 .and. grid%mass(a) == 0.005_wp .and. &
            grid%mass(b) == 0.001_wp, "light nodes without a heavy neighbour are left alone")
        call small_grid(grid, 0.0_wp)
        grid%mass(a) = 0.005_wp
        grid%mass(b) = 1.0_wp
        call settle_light_nodes(grid, 1)
        call check(suite, grid%nlight == 0 .and. grid%mass(a) == 0.005_wp, &
            "light_mass 0: no light node")
    end subroutine test_alone

end program test_mpm_kernel_light
