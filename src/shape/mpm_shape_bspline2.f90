!> Quadratic B-spline shape functions, boundary-modified at the grid ends.
!>
!> The 1D weight of node i is the uniform quadratic B-spline centred on it (knots at the
!> cell midpoints), with r = (x_p - x_i) / L:
!>
!>     N(r) = 3/4 - r**2                 |r| <= 1/2
!>     N(r) = (3/2 - |r|)**2 / 2         1/2 <= |r| <= 3/2
!>     N(r) = 0                          otherwise
!>
!> C1 everywhere, three nodes per axis. Within half a cell of a grid end the node beyond it
!> (outside the grid) is folded into the two nodes inside (mpm_shape::fold_ghost_nodes): the
!> weights sum to one, reproduce linear functions and stay C1 and non-negative up to the
!> grid ends. The particle domain (lp) is not used. 2D and 3D weights are tensor products.
module mpm_shape_bspline2
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    use mpm_shape, only: shape_type, shape_name_width, fold_ghost_nodes
    implicit none
    private
    public :: bspline2_shape_type, bspline2_weights_1d

    integer, parameter :: width = 3
        !! nodes per axis: the support of a node is three cells wide

    !> Quadratic B-splines: a particle touches 3 nodes per direction.
    type, extends(shape_type) :: bspline2_shape_type
    contains
        procedure :: weights_1d => bspline2_shape_weights_1d
        procedure :: nodes_per_axis => bspline2_nodes_per_axis
        procedure :: halo_width => bspline2_halo_width
        procedure :: names => bspline2_names
        procedure :: weights_all => bspline2_weights_all
    end type bspline2_shape_type

    !> The 1D routine under the name mpm_shape_spline_weights_all.inc calls.
    interface spline_weights_1d
        module procedure bspline2_weights_1d
    end interface spline_weights_1d

contains

    !> 1D quadratic B-spline weights of the three nodes nearest to xi (xi in cell units from
    !> the origin; clamped to the grid, 0 .. ncells).
    pure subroutine bspline2_weights_1d(xi, dx, ncells, first, w, dw)
        real(wp), intent(in) :: xi
            !! particle coordinate in cell units, (x - origin) / dx [-]
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: ncells
            !! cells along this axis
        integer, intent(out) :: first
            !! first of the three nodes (0-based; -1 next to the lower end, weight zero)
        real(wp), intent(out) :: w(width)
            !! weights [-]
        real(wp), intent(out) :: dw(width)
            !! derivatives [1/m]

        real(wp) :: x, t, inv_dx

        inv_dx = 1.0_wp/dx
        x = min(max(xi, 0.0_wp), real(ncells, wp))
        ! the middle node is the nearest one; t in [-1/2, 1/2] from it
        first = floor(x + 0.5_wp) - 1
        t = x - real(first + 1, wp)
        w(1) = 0.5_wp*(0.5_wp - t)**2
        w(2) = 0.75_wp - t*t
        w(3) = 0.5_wp*(0.5_wp + t)**2
        dw(1) = -(0.5_wp - t)*inv_dx
        dw(2) = -2.0_wp*t*inv_dx
        dw(3) = (0.5_wp + t)*inv_dx
        if (first < 0 .or. first + width - 1 > ncells) call fold_ghost_nodes(first, ncells, w, dw)
    end subroutine bspline2_weights_1d

    pure subroutine bspline2_shape_weights_1d(self, xi, lp, dx, ncells, first, w, dw)
        class(bspline2_shape_type), intent(in) :: self
        real(wp), intent(in) :: xi, lp, dx
        integer, intent(in) :: ncells
        integer, intent(out) :: first
        real(wp), intent(out), contiguous :: w(:), dw(:)

        call bspline2_weights_1d(xi, dx, ncells, first, w, dw)
    end subroutine bspline2_shape_weights_1d

    pure integer function bspline2_nodes_per_axis(self)
        class(bspline2_shape_type), intent(in) :: self
        bspline2_nodes_per_axis = width
    end function bspline2_nodes_per_axis

    !> Three node layers at a cut c, as cpGIMP: a particle of the slab below it (cells < c)
    !> touches nodes up to c + 1, one of the slab above (cells >= c) nodes from c - 1; a
    !> particle in a slab is at least a cell from its grid's end at a cut, where the
    !> boundary modification therefore does nothing.
    pure integer function bspline2_halo_width(self)
        class(bspline2_shape_type), intent(in) :: self
        bspline2_halo_width = 3
    end function bspline2_halo_width

    pure subroutine bspline2_names(self, names)
        class(bspline2_shape_type), intent(in) :: self
        character(len=shape_name_width), allocatable, intent(out) :: names(:)
        names = [character(len=shape_name_width) :: "bspline2", "quadratic_bspline"]
    end subroutine bspline2_names

    !> The 1D weights of every particle along every axis (mpm_shape_spline_weights_all.inc).
    subroutine bspline2_weights_all(self, grid, x, lp, first, w, dw)
        class(bspline2_shape_type), intent(in) :: self
            !! the shape function
        include "mpm_shape_spline_weights_all.inc"
    end subroutine bspline2_weights_all

end module mpm_shape_bspline2
