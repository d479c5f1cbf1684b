!> Linear (bilinear in 2D, trilinear in 3D) hat shape functions.
module mpm_shape_linear
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    use mpm_shape, only: shape_type, shape_name_width
    implicit none
    private
    public :: linear_shape_type, linear_weights_1d

    integer, parameter :: width = 2
        !! nodes per axis: the two nodes of the particle's cell

    !> Standard MPM hat functions: a particle touches the 2**dim nodes of its cell.
    type, extends(shape_type) :: linear_shape_type
    contains
        procedure :: weights_1d => linear_shape_weights_1d
        procedure :: nodes_per_axis => linear_nodes_per_axis
        procedure :: halo_width => linear_halo_width
        procedure :: names => linear_names
        procedure :: weights_all => linear_weights_all
    end type linear_shape_type

contains

    !> 1D hat weights of the two nodes of the cell holding xi (xi in cell units from the origin).
    pure subroutine linear_weights_1d(xi, ncells, dx, first, w, dw)
        real(wp), intent(in) :: xi
            !! particle coordinate in cell units, (x - origin) / dx [-]
        integer, intent(in) :: ncells
            !! cells along this axis
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(out) :: first
            !! left node of the cell (0-based)
        real(wp), intent(out) :: w(width)
            !! weights of nodes first, first + 1 [-]
        real(wp), intent(out) :: dw(width)
            !! derivatives [1/m]

        real(wp) :: r

        first = min(max(floor(xi), 0), ncells - 1)
        r = xi - real(first, wp)
        w = [1.0_wp - r, r]
        dw = [-1.0_wp/dx, 1.0_wp/dx]
    end subroutine linear_weights_1d

    pure subroutine linear_shape_weights_1d(self, xi, lp, dx, ncells, first, w, dw)
        class(linear_shape_type), intent(in) :: self
        real(wp), intent(in) :: xi, lp, dx
        integer, intent(in) :: ncells
        integer, intent(out) :: first
        real(wp), intent(out), contiguous :: w(:), dw(:)

        call linear_weights_1d(xi, ncells, dx, first, w, dw)
    end subroutine linear_shape_weights_1d

    pure integer function linear_nodes_per_axis(self)
        class(linear_shape_type), intent(in) :: self
        linear_nodes_per_axis = width
    end function linear_nodes_per_axis

    !> Three node layers at a cut: a particle of a slab touches only the node of its own
    !> cut (the cut's node layer), but the slab's grid keeps one ghost cell beyond each cut
    !> (mpm_decomposition: a particle moves up to a cell in a step and stays on its image's
    !> grid until it migrates), and the images hold the same sums on every node layer their
    !> grids share (the running contact loads of those nodes follow them at a rebalance).
    pure integer function linear_halo_width(self)
        class(linear_shape_type), intent(in) :: self
        linear_halo_width = 3
    end function linear_halo_width

    pure subroutine linear_names(self, names)
        class(linear_shape_type), intent(in) :: self
        character(len=shape_name_width), allocatable, intent(out) :: names(:)
        names = [character(len=shape_name_width) :: "linear"]
    end subroutine linear_names

    !> The linear weights of the particles given along every axis (serial, as every
    !> weights_all: mpm_stencil::compute_stencils threads over blocks of particles).
    subroutine linear_weights_all(self, grid, x, lp, first, w, dw)
        class(linear_shape_type), intent(in) :: self
        type(grid_type), intent(in) :: grid
        real(wp), intent(in) :: x(:, :), lp(:, :)
        integer, intent(out) :: first(:, :)
        real(wp), intent(out) :: w(:, :, :), dw(:, :, :)

        integer :: p, a
        real(wp) :: xi, w2(width), dw2(width)

        do p = 1, size(x, 2)
            do a = 1, grid%dim
                xi = (x(a, p) - grid%origin(a))/grid%dx
                call linear_weights_1d(xi, grid%ncells(a), grid%dx, first(a, p), w2, dw2)
                w(:, a, p) = w2
                dw(:, a, p) = dw2(1:width - 1)
            end do
        end do
    end subroutine linear_weights_all

end module mpm_shape_linear
