!> Helpers shared by the suites that work on made-up grids (shape functions, stencils): a grid
!> of given cells without a case file, and the "2D" / "3D" label of a dimension.
module mpm_testing_grid
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    implicit none
    private
    public :: made_up_grid, dims

contains

    !> A grid of ncells(1:dim) cells of dx from origin (node counts and totals set, nothing
    !> allocated).
    subroutine made_up_grid(grid, dim, ncells, dx, origin)
        type(grid_type), intent(out) :: grid
            !! the grid
        integer, intent(in) :: dim
            !! space dimensions
        integer, intent(in) :: ncells(3)
            !! cells per axis (first dim used)
        real(wp), intent(in) :: dx
            !! cell size [m]
        real(wp), intent(in) :: origin(3)
            !! position of node (0, 0, 0) [m]

        grid%dim = dim
        grid%ncells = 1
        grid%ncells(1:dim) = ncells(1:dim)
        grid%nn = 1
        grid%nn(1:dim) = grid%ncells(1:dim) + 1
        grid%nnodes = product(grid%nn)
        grid%dx = dx
        grid%origin = origin
    end subroutine made_up_grid

    !> "2D" or "3D".
    function dims(dim) result(text)
        integer, intent(in) :: dim
            !! space dimensions
        character(len=2) :: text
        write (text, "(i1,a)") dim, "D"
    end function dims

end module mpm_testing_grid
