!> Shape functions: the abstract interface and the per-particle stencil of nodes.
!>
!> A shape function evaluates, for one particle, the nodes it touches with their weights
!> N_i(x_p) and gradients grad N_i(x_p). Concrete shape functions are extensions of
!> `shape_type` in their own modules (linear, cpGIMP); the solver sees only this interface.
!> Evaluations are `pure` so they can run inside threaded particle loops.
module mpm_shape
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    implicit none
    private
    public :: shape_type, stencil_type, max_stencil, tensor_product

    integer, parameter :: max_stencil = 27
        !! largest number of nodes one particle touches (3 per direction in 3D)

    !> Nodes, weights and weight gradients of one particle.
    type :: stencil_type
        integer :: count = 0
            !! number of nodes used
        integer :: node(max_stencil) = 0
            !! linear node indices
        real(wp) :: w(max_stencil) = 0.0_wp
            !! weights N_i(x_p) [-]
        real(wp) :: dw(3, max_stencil) = 0.0_wp
            !! weight gradients dN_i/dx (first dim components used) [1/m]
    end type stencil_type

    !> A shape function: a tensor product of 1D weights.
    type, abstract :: shape_type
    contains
        procedure(weights_1d_interface), deferred :: weights_1d
            !! 1D weights and derivatives of the nodes around a coordinate
        procedure(nodes_per_axis_interface), deferred :: nodes_per_axis
            !! nodes per axis a particle can touch (2 linear, 3 cpGIMP)
        procedure(weights_all_interface), deferred :: weights_all
            !! weights_1d for every particle and axis (one call per step, threaded)
        procedure :: evaluate
            !! nodes, weights and gradients of one particle
    end type shape_type

    abstract interface
        !> 1D weights of the nodes first .. first + nodes_per_axis - 1 (0-based) around the
        !> coordinate xi (in cell units from the grid origin) of a particle of half-size lp.
        !> Nodes outside the grid may be named; their weights are zero.
        pure subroutine weights_1d_interface(self, xi, lp, dx, ncells, first, w, dw)
            import :: shape_type, wp
            class(shape_type), intent(in) :: self
                !! the shape function
            real(wp), intent(in) :: xi
                !! particle coordinate in cell units, (x - origin) / dx [-]
            real(wp), intent(in) :: lp
                !! particle half-size [m]; unused by linear shape functions
            real(wp), intent(in) :: dx
                !! cell size [m]
            integer, intent(in) :: ncells
                !! cells along this axis
            integer, intent(out) :: first
                !! first node (0-based)
            real(wp), intent(out) :: w(3)
                !! weights [-] (unused entries zero)
            real(wp), intent(out) :: dw(3)
                !! derivatives [1/m] (unused entries zero)
        end subroutine weights_1d_interface

        !> weights_1d of every particle along every axis of the grid.
        subroutine weights_all_interface(self, grid, x, lp, first, w, dw)
            import :: shape_type, grid_type, wp
            class(shape_type), intent(in) :: self
                !! the shape function
            type(grid_type), intent(in) :: grid
                !! grid geometry
            real(wp), intent(in) :: x(:, :)
                !! particle positions (dim, n) [m]
            real(wp), intent(in) :: lp(:, :)
                !! particle half-sizes (dim, n) [m]
            integer, intent(out) :: first(:, :)
                !! first node per axis, 0-based (dim, n)
            real(wp), intent(out) :: w(:, :, :)
                !! weights (nodes_per_axis, dim, n) [-]
            real(wp), intent(out) :: dw(:, :, :)
                !! derivatives of the first nodes_per_axis - 1 nodes (nodes_per_axis - 1, dim,
                !! n) [1/m]; the last one is minus their sum (the weights sum to one), so it
                !! is not stored
        end subroutine weights_all_interface

        !> Nodes per axis that a particle can touch.
        pure integer function nodes_per_axis_interface(self)
            import :: shape_type
            class(shape_type), intent(in) :: self
                !! the shape function
        end function nodes_per_axis_interface
    end interface

contains

    !> Stencil of a particle at `xp` with GIMP half-sizes `lp`: the tensor product of the
    !> 1D weights, nodes outside the grid and zero weights skipped.
    pure subroutine evaluate(self, grid, xp, lp, st)
        class(shape_type), intent(in) :: self
            !! the shape function
        type(grid_type), intent(in) :: grid
            !! grid geometry (nn, dx, origin)
        real(wp), intent(in) :: xp(:)
            !! particle position (dim) [m]
        real(wp), intent(in) :: lp(:)
            !! particle half-sizes (dim) [m]; unused by linear shape functions
        type(stencil_type), intent(out) :: st
            !! nodes, weights, gradients

        integer :: a, first(3)
        real(wp) :: w1(3, 3), dw1(3, 3)

        first = 0
        w1 = 0.0_wp
        dw1 = 0.0_wp
        w1(1, 3) = 1.0_wp
        do a = 1, grid%dim
            call self%weights_1d((xp(a) - grid%origin(a))/grid%dx, lp(a), grid%dx, &
                grid%ncells(a), first(a), w1(:, a), dw1(:, a))
        end do
        call tensor_product(grid, first, self%nodes_per_axis(), w1, dw1, st)
    end subroutine evaluate

    !> Tensor-product stencil from per-axis weights.
    !>
    !> Axis `a` uses nodes first(a) .. first(a) + nper - 1 (0-based) with weights w1(:, a) and
    !> derivatives dw1(:, a). Nodes outside the grid and zero weights are skipped.
    pure subroutine tensor_product(grid, first, nper, w1, dw1, st)
        type(grid_type), intent(in) :: grid
            !! grid geometry
        integer, intent(in) :: first(3)
            !! first node along each axis (0-based)
        integer, intent(in) :: nper
            !! nodes per axis (2 or 3)
        real(wp), intent(in) :: w1(3, 3)
            !! 1D weights (node, axis) [-]
        real(wp), intent(in) :: dw1(3, 3)
            !! 1D weight derivatives (node, axis) [1/m]
        type(stencil_type), intent(out) :: st
            !! resulting stencil

        integer :: i, j, k, ii, jj, kk, nk, c
        real(wp) :: wij

        c = 0
        if (grid%dim == 2) then
            nk = 1
        else
            nk = nper
        end if
        do k = 1, nk
            kk = first(3) + k - 1
            if (kk < 0 .or. kk >= grid%nn(3)) cycle
            do j = 1, nper
                jj = first(2) + j - 1
                if (jj < 0 .or. jj >= grid%nn(2)) cycle
                do i = 1, nper
                    ii = first(1) + i - 1
                    if (ii < 0 .or. ii >= grid%nn(1)) cycle
                    if (grid%dim == 2) then
                        wij = w1(i, 1)*w1(j, 2)
                        if (wij <= 0.0_wp) cycle
                        c = c + 1
                        st%w(c) = wij
                        st%dw(1, c) = dw1(i, 1)*w1(j, 2)
                        st%dw(2, c) = w1(i, 1)*dw1(j, 2)
                        st%dw(3, c) = 0.0_wp
                    else
                        wij = w1(i, 1)*w1(j, 2)*w1(k, 3)
                        if (wij <= 0.0_wp) cycle
                        c = c + 1
                        st%w(c) = wij
                        st%dw(1, c) = dw1(i, 1)*w1(j, 2)*w1(k, 3)
                        st%dw(2, c) = w1(i, 1)*dw1(j, 2)*w1(k, 3)
                        st%dw(3, c) = w1(i, 1)*w1(j, 2)*dw1(k, 3)
                    end if
                    st%node(c) = 1 + ii + grid%nn(1)*(jj + grid%nn(2)*kk)
                end do
            end do
        end do
        st%count = c
    end subroutine tensor_product

end module mpm_shape
