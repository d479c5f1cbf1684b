!> Linear (bilinear in 2D, trilinear in 3D) hat shape functions.
module mpm_shape_linear
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    use mpm_shape, only: shape_type, stencil_type, tensor_product
    implicit none
    private
    public :: linear_shape_type, linear_weights_1d

    !> Standard MPM hat functions: a particle touches the 2**dim nodes of its cell.
    type, extends(shape_type) :: linear_shape_type
    contains
        procedure :: evaluate => linear_evaluate
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
        real(wp), intent(out) :: w(3)
            !! weights of nodes first, first + 1 (third unused) [-]
        real(wp), intent(out) :: dw(3)
            !! derivatives [1/m]

        real(wp) :: r

        first = min(max(floor(xi), 0), ncells - 1)
        r = xi - real(first, wp)
        w = [1.0_wp - r, r, 0.0_wp]
        dw = [-1.0_wp/dx, 1.0_wp/dx, 0.0_wp]
    end subroutine linear_weights_1d

    pure subroutine linear_evaluate(self, grid, xp, lp, st)
        class(linear_shape_type), intent(in) :: self
        type(grid_type), intent(in) :: grid
        real(wp), intent(in) :: xp(:)
        real(wp), intent(in) :: lp(:)
        type(stencil_type), intent(out) :: st

        integer :: a, first(3)
        real(wp) :: w1(3, 3), dw1(3, 3)

        first = 0
        w1 = 0.0_wp
        dw1 = 0.0_wp
        w1(1, 3) = 1.0_wp
        do a = 1, grid%dim
            call linear_weights_1d((xp(a) - grid%origin(a))/grid%dx, grid%ncells(a), grid%dx, &
                first(a), w1(:, a), dw1(:, a))
        end do
        call tensor_product(grid, first, 2, w1, dw1, st)
    end subroutine linear_evaluate

end module mpm_shape_linear
