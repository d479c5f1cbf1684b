!> Cubic B-spline shape functions, boundary-modified at the grid ends.
!>
!> The 1D weight of node i is the uniform cubic B-spline centred on it (knots at the nodes),
!> with r = (x_p - x_i) / L:
!>
!>     N(r) = 2/3 - r**2 + |r|**3 / 2    |r| <= 1
!>     N(r) = (2 - |r|)**3 / 6           1 <= |r| <= 2
!>     N(r) = 0                          otherwise
!>
!> C2 everywhere, four nodes per axis. Within a cell of a grid end the node beyond it
!> (outside the grid) is folded into the two nodes inside (mpm_shape::fold_ghost_nodes): the
!> weights sum to one, reproduce linear functions and stay C2 and non-negative up to the
!> grid ends. The particle domain (lp) is not used. 2D and 3D weights are tensor products.
module mpm_shape_bspline3
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    use mpm_shape, only: shape_type, shape_name_width, fold_ghost_nodes
    implicit none
    private
    public :: bspline3_shape_type, bspline3_weights_1d

    integer, parameter :: width = 4
        !! nodes per axis: the support of a node is four cells wide

    !> Cubic B-splines: a particle touches 4 nodes per direction.
    type, extends(shape_type) :: bspline3_shape_type
    contains
        procedure :: weights_1d => bspline3_shape_weights_1d
        procedure :: nodes_per_axis => bspline3_nodes_per_axis
        procedure :: halo_width => bspline3_halo_width
        procedure :: names => bspline3_names
        procedure :: weights_all => bspline3_weights_all
    end type bspline3_shape_type

    !> The 1D routine under the name mpm_shape_spline_weights_all.inc calls.
    interface spline_weights_1d
        module procedure bspline3_weights_1d
    end interface spline_weights_1d

contains

    !> 1D cubic B-spline weights of the four nodes nearest to xi (xi in cell units from the
    !> origin; clamped to the grid, 0 .. ncells).
    pure subroutine bspline3_weights_1d(xi, dx, ncells, first, w, dw)
        real(wp), intent(in) :: xi
            !! particle coordinate in cell units, (x - origin) / dx [-]
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: ncells
            !! cells along this axis
        integer, intent(out) :: first
            !! first of the four nodes (0-based; -1 next to the lower end, weight zero)
        real(wp), intent(out) :: w(width)
            !! weights [-]
        real(wp), intent(out) :: dw(width)
            !! derivatives [1/m]

        real(wp) :: x, t, s, inv_dx

        inv_dx = 1.0_wp/dx
        x = min(max(xi, 0.0_wp), real(ncells, wp))
        ! nodes 2 and 3 are those of the particle's cell (the last cell at the upper end);
        ! t in [0, 1] from node 2, s = 1 - t from node 3
        first = min(floor(x), ncells - 1) - 1
        t = x - real(first + 1, wp)
        s = 1.0_wp - t
        w(1) = s**3/6.0_wp
        w(2) = 2.0_wp/3.0_wp - t*t*(1.0_wp - 0.5_wp*t)
        w(3) = 2.0_wp/3.0_wp - s*s*(1.0_wp - 0.5_wp*s)
        w(4) = t**3/6.0_wp
        dw(1) = -0.5_wp*s*s*inv_dx
        dw(2) = t*(1.5_wp*t - 2.0_wp)*inv_dx
        dw(3) = -s*(1.5_wp*s - 2.0_wp)*inv_dx
        dw(4) = 0.5_wp*t*t*inv_dx
        if (first < 0 .or. first + width - 1 > ncells) then
            call fold_ghost_nodes(first, ncells, w, dw)
            ! at the grid end itself the folded weight of the next node is 1/6 - 1/6 in
            ! rounding (-3e-17), not zero
            w = max(w, 0.0_wp)
        end if
    end subroutine bspline3_weights_1d

    pure subroutine bspline3_shape_weights_1d(self, xi, lp, dx, ncells, first, w, dw)
        class(bspline3_shape_type), intent(in) :: self
        real(wp), intent(in) :: xi, lp, dx
        integer, intent(in) :: ncells
        integer, intent(out) :: first
        real(wp), intent(out), contiguous :: w(:), dw(:)

        call bspline3_weights_1d(xi, dx, ncells, first, w, dw)
    end subroutine bspline3_shape_weights_1d

    pure integer function bspline3_nodes_per_axis(self)
        class(bspline3_shape_type), intent(in) :: self
        bspline3_nodes_per_axis = width
    end function bspline3_nodes_per_axis

    !> Three node layers at a cut c, as cpGIMP: a particle of the slab below it (cells < c)
    !> touches nodes up to c + 1 (two beyond its cell's left node), one of the slab above
    !> (cells >= c) nodes from c - 1; a particle in a slab is at least a cell from its
    !> grid's end at a cut (the ghost cell), where the boundary modification does nothing.
    pure integer function bspline3_halo_width(self)
        class(bspline3_shape_type), intent(in) :: self
        bspline3_halo_width = 3
    end function bspline3_halo_width

    pure subroutine bspline3_names(self, names)
        class(bspline3_shape_type), intent(in) :: self
        character(len=shape_name_width), allocatable, intent(out) :: names(:)
        names = [character(len=shape_name_width) :: "bspline3", "cubic_bspline"]
    end subroutine bspline3_names

    !> The 1D weights of every particle along every axis (mpm_shape_spline_weights_all.inc).
    subroutine bspline3_weights_all(self, grid, x, lp, first, w, dw)
        class(bspline3_shape_type), intent(in) :: self
            !! the shape function
        include "mpm_shape_spline_weights_all.inc"
    end subroutine bspline3_weights_all

end module mpm_shape_bspline3
