!> Contiguous-particle GIMP (cpGIMP) shape functions.
!>
!> The 1D weight is the average of the linear hat function N_i over the particle domain
!> [x_p - l_p, x_p + l_p] (Bardenhagen & Kober 2004). With r = x_p - x_i, cell size L and
!> half-size l_p <= L/2:
!>
!>     S(r) = 1 - (r**2 + l_p**2) / (2 L l_p)        |r| <  l_p
!>     S(r) = 1 - |r| / L                            l_p <= |r| <= L - l_p
!>     S(r) = (L + l_p - |r|)**2 / (4 L l_p)          L - l_p < |r| < L + l_p
!>     S(r) = 0                                      otherwise
!>
!> and dS/dx_p the analytic derivative of each piece, evaluated without branches as the
!> difference of the hat's antiderivative across the particle domain (gimp_weight_cells).
!> 2D and 3D weights are tensor products.
!> The particle domain follows the deformation (the solver updates l_p from F); next to a
!> domain face it is truncated at the face so that the weights keep summing to one.
module mpm_shape_gimp
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    use mpm_shape, only: shape_type, shape_name_width
    implicit none
    private
    public :: gimp_shape_type, gimp_weight, gimp_weights_1d

    integer, parameter :: width = 3
        !! nodes per axis: lp <= dx/2 keeps the support within three nodes

    !> cpGIMP: a particle touches up to 3 nodes per direction (lp <= dx/2).
    type, extends(shape_type) :: gimp_shape_type
    contains
        procedure :: weights_1d => gimp_shape_weights_1d
        procedure :: nodes_per_axis => gimp_nodes_per_axis
        procedure :: halo_width => gimp_halo_width
        procedure :: names => gimp_names
        procedure :: weights_all => gimp_weights_all
    end type gimp_shape_type

contains

    !> cpGIMP weight and derivative of one node for a particle at distance r = x_p - x_i.
    pure elemental subroutine gimp_weight(r, lp, dx, s, ds)
        real(wp), intent(in) :: r
            !! particle position minus node position [m]
        real(wp), intent(in) :: lp
            !! particle half-size, 0 < lp <= dx/2 [m]
        real(wp), intent(in) :: dx
            !! cell size L [m]
        real(wp), intent(out) :: s
            !! weight [-]
        real(wp), intent(out) :: ds
            !! derivative with respect to x_p [1/m]

        call gimp_weight_cells(r/dx, lp/dx, 0.5_wp/(lp/dx), 1.0_wp/dx, s, ds)
    end subroutine gimp_weight

    !> cpGIMP weight in cell units, without branches: the mean of the hat over the particle
    !> domain is (H(r + l) - H(r - l)) / (2 l), H(t) = t - t |t| / 2 the antiderivative of the
    !> hat 1 - |t| (t clamped to [-1, 1]), and its derivative (hat(r + l) - hat(r - l)) / (2 l).
    !> The same pieces as the piecewise form of the module documentation, exact zeros beyond
    !> the support, and no mispredicted branches (the piece of a node depends on where the
    !> particle is). The difference loses the digits of l: about 1e-16 / l of the weight.
    pure elemental subroutine gimp_weight_cells(r, l, half_inv_l, inv_dx, s, ds)
        real(wp), intent(in) :: r
            !! (x_p - x_i) / L [-]
        real(wp), intent(in) :: l
            !! lp / L, in (0, 1/2] [-]
        real(wp), intent(in) :: half_inv_l
            !! 1 / (2 l) [-]
        real(wp), intent(in) :: inv_dx
            !! 1 / L [1/m]
        real(wp), intent(out) :: s
            !! weight [-]
        real(wp), intent(out) :: ds
            !! derivative with respect to x_p [1/m]

        real(wp) :: hi, lo

        hi = max(-1.0_wp, min(1.0_wp, r + l))
        lo = max(-1.0_wp, min(1.0_wp, r - l))
        s = ((hi - lo) - 0.5_wp*(hi*abs(hi) - lo*abs(lo)))*half_inv_l
        ds = (abs(lo) - abs(hi))*half_inv_l*inv_dx
    end subroutine gimp_weight_cells

    !> 1D cpGIMP weights of the three nodes around a particle.
    pure subroutine gimp_weights_1d(xi, lp, dx, ncells, first, w, dw)
        real(wp), intent(in) :: xi
            !! particle coordinate in cell units, (x - origin) / dx [-]
        real(wp), intent(in) :: lp
            !! particle half-size [m]
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: ncells
            !! cells along this axis
        integer, intent(out) :: first
            !! first of the three nodes (0-based; may be -1 or past the grid, skipped later)
        real(wp), intent(out) :: w(width)
            !! weights [-]
        real(wp), intent(out) :: dw(width)
            !! derivatives [1/m]

        integer :: k
        real(wp) :: l, half_inv_l, inv_dx

        ! The particle domain is kept inside the grid (truncated at the domain faces) so the
        ! weights still sum to one next to a boundary; lp <= dx/2 keeps the 3-node support.
        inv_dx = 1.0_wp/dx
        l = min(lp*inv_dx, 0.5_wp, xi, real(ncells, wp) - xi)
        l = max(l, 1.0e-6_wp)
        half_inv_l = 0.5_wp/l
        ! In the left half of a cell the node two cells to the right is out of reach
        ! (distance >= 1.5 dx >= dx + lp), and symmetrically on the right half: the first
        ! node is the cell's left node minus one in the left half, without a branch
        first = floor(xi - 0.5_wp)
        do k = 1, width
            call gimp_weight_cells(xi - real(first + k - 1, wp), l, half_inv_l, inv_dx, w(k), &
                dw(k))
        end do
    end subroutine gimp_weights_1d

    pure subroutine gimp_shape_weights_1d(self, xi, lp, dx, ncells, first, w, dw)
        class(gimp_shape_type), intent(in) :: self
        real(wp), intent(in) :: xi, lp, dx
        integer, intent(in) :: ncells
        integer, intent(out) :: first
        real(wp), intent(out), contiguous :: w(:), dw(:)

        ! contiguous: no copy in and out here, so this wrapper stays small and the optimiser
        ! inlines gimp_weights_1d into gimp_weights_all as it did before the wrapper took
        ! arrays of any width (with a copy it did not, and the weights changed in their last
        ! bits)
        call gimp_weights_1d(xi, lp, dx, ncells, first, w, dw)
    end subroutine gimp_shape_weights_1d

    pure integer function gimp_nodes_per_axis(self)
        class(gimp_shape_type), intent(in) :: self
        gimp_nodes_per_axis = width
    end function gimp_nodes_per_axis

    !> Three node layers at a cut c: a particle of the slab below it (cells < c) touches
    !> nodes up to c + 1, one of the slab above (cells >= c) nodes from c - 1.
    pure integer function gimp_halo_width(self)
        class(gimp_shape_type), intent(in) :: self
        gimp_halo_width = 3
    end function gimp_halo_width

    pure subroutine gimp_names(self, names)
        class(gimp_shape_type), intent(in) :: self
        character(len=shape_name_width), allocatable, intent(out) :: names(:)
        names = [character(len=shape_name_width) :: "cpgimp", "gimp"]
    end subroutine gimp_names

    !> The weights of the particles given along every axis, as gimp_weights_1d gives them
    !> (the same operations, so the same bits), over blocks of particles: along one axis at
    !> a time, the block's positions are copied to contiguous scratch, the weights are formed
    !> for the whole block in vector registers (several particles per instruction) and
    !> stored to the particles' stencils afterwards. Serial, as every weights_all: the
    !> stencils thread over blocks of particles (mpm_stencil::compute_stencils).
    subroutine gimp_weights_all(self, grid, x, lp, first, w, dw)
        class(gimp_shape_type), intent(in) :: self
        type(grid_type), intent(in) :: grid
        real(wp), intent(in) :: x(:, :), lp(:, :)
        integer, intent(out) :: first(:, :)
        real(wp), intent(out) :: w(:, :, :), dw(:, :, :)

        integer, parameter :: block = 64
            !! particles per block (their scratch stays in the first-level cache)
        integer :: p0, nb, j, a, k
        integer :: fs(block)
        real(wp) :: xb(block), lb(block), ws(block, width), dws(block, width), inv_dx, &
            origin, dx, cells, xi, l, half_inv_l

        dx = grid%dx
        inv_dx = 1.0_wp/dx
        do p0 = 1, size(x, 2), block
            nb = min(block, size(x, 2) - p0 + 1)
            do a = 1, grid%dim
                origin = grid%origin(a)
                cells = real(grid%ncells(a), wp)
                do j = 1, nb
                    xb(j) = x(a, p0 + j - 1)
                    lb(j) = lp(a, p0 + j - 1)
                end do
                ! gimp_weights_1d, particle by particle of the block
                do j = 1, nb
                    xi = (xb(j) - origin)/dx
                    l = min(lb(j)*inv_dx, 0.5_wp, xi, cells - xi)
                    l = max(l, 1.0e-6_wp)
                    half_inv_l = 0.5_wp/l
                    fs(j) = floor(xi - 0.5_wp)
                    do k = 1, width
                        call gimp_weight_cells(xi - real(fs(j) + k - 1, wp), l, half_inv_l, &
                            inv_dx, ws(j, k), dws(j, k))
                    end do
                end do
                do j = 1, nb
                    first(a, p0 + j - 1) = fs(j)
                    w(:, a, p0 + j - 1) = ws(j, :)
                    dw(:, a, p0 + j - 1) = dws(j, 1:width - 1)
                end do
            end do
        end do
    end subroutine gimp_weights_all

end module mpm_shape_gimp
