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
!> The particle domain follows the deformation (the solver updates l_p from F). Next to a
!> domain face the weight of the node beyond the face is folded onto the face node, so that
!> the weights keep summing to one on the nodes of the grid and no node takes a weight that
!> vanishes under a finite gradient.
module mpm_shape_gimp
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    use mpm_shape, only: shape_type
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

        ! lp <= dx/2 keeps the 3-node support. The domain is not shrunk at a domain face:
        ! shrunk to the particle's distance from the face, it gave the next row of nodes a
        ! weight that vanishes with that distance under a gradient that does not (a sliver of
        ! mass under a full force); the weight beyond the face is folded onto the face node
        ! below instead.
        inv_dx = 1.0_wp/dx
        l = min(lp*inv_dx, 0.5_wp)
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
        ! A node beyond a domain face (first = -1, or first + 2 = ncells + 1) is tied to the
        ! face node: its weight and derivative go to the face node (as the boundary-modified
        ! B-splines do), so the weights sum to one inside the grid and the face node moves
        ! the part of the domain beyond the face
        if (first < 0) then
            w(2) = w(2) + w(1)
            dw(2) = dw(2) + dw(1)
            w(1) = 0.0_wp
            dw(1) = 0.0_wp
        end if
        if (first + width - 1 > ncells) then
            w(width - 1) = w(width - 1) + w(width)
            dw(width - 1) = dw(width - 1) + dw(width)
            w(width) = 0.0_wp
            dw(width) = 0.0_wp
        end if
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

    subroutine gimp_weights_all(self, grid, x, lp, first, w, dw)
        class(gimp_shape_type), intent(in) :: self
        type(grid_type), intent(in) :: grid
        real(wp), intent(in) :: x(:, :), lp(:, :)
        integer, intent(out) :: first(:, :)
        real(wp), intent(out) :: w(:, :, :), dw(:, :, :)

        integer :: p, a
        real(wp) :: xi, w3(width), dw3(width)

        !$omp parallel do default(none) schedule(static) shared(grid, x, lp, first, w, dw) &
        !$omp private(p, a, xi, w3, dw3)
        do p = 1, size(x, 2)
            do a = 1, grid%dim
                xi = (x(a, p) - grid%origin(a))/grid%dx
                call gimp_weights_1d(xi, lp(a, p), grid%dx, grid%ncells(a), first(a, p), w3, dw3)
                w(:, a, p) = w3
                dw(:, a, p) = dw3(1:width - 1)
            end do
        end do
        !$omp end parallel do
    end subroutine gimp_weights_all

end module mpm_shape_gimp
