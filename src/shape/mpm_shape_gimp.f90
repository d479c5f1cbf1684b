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
!> and dS/dx_p the analytic derivative of each piece. 2D and 3D weights are tensor products.
!> The particle domain follows the deformation (the solver updates l_p from F); next to a
!> domain face it is truncated at the face so that the weights keep summing to one.
module mpm_shape_gimp
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    use mpm_shape, only: shape_type
    implicit none
    private
    public :: gimp_shape_type, gimp_weight, gimp_weights_1d

    !> cpGIMP: a particle touches up to 3 nodes per direction (lp <= dx/2).
    type, extends(shape_type) :: gimp_shape_type
    contains
        procedure :: weights_1d => gimp_shape_weights_1d
        procedure :: nodes_per_axis => gimp_nodes_per_axis
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

        real(wp) :: ar

        ar = abs(r)
        if (ar < lp) then
            s = 1.0_wp - (r*r + lp*lp)/(2.0_wp*dx*lp)
            ds = -r/(dx*lp)
        else if (ar <= dx - lp) then
            s = 1.0_wp - ar/dx
            ds = -sign(1.0_wp, r)/dx
        else if (ar < dx + lp) then
            s = (dx + lp - ar)**2/(4.0_wp*dx*lp)
            ds = -sign(1.0_wp, r)*(dx + lp - ar)/(2.0_wp*dx*lp)
        else
            s = 0.0_wp
            ds = 0.0_wp
        end if
    end subroutine gimp_weight

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
        real(wp), intent(out) :: w(3)
            !! weights [-]
        real(wp), intent(out) :: dw(3)
            !! derivatives [1/m]

        integer :: cell, k
        real(wp) :: lpc

        ! The particle domain is kept inside the grid (truncated at the domain faces) so the
        ! weights still sum to one next to a boundary; lp <= dx/2 keeps the 3-node support.
        lpc = min(lp, 0.5_wp*dx, xi*dx, (real(ncells, wp) - xi)*dx)
        lpc = max(lpc, 1.0e-6_wp*dx)
        cell = floor(xi)
        ! In the left half of a cell the node two cells to the right is out of reach
        ! (distance >= 1.5 dx >= dx + lp), and symmetrically on the right half.
        if (xi - real(cell, wp) < 0.5_wp) then
            first = cell - 1
        else
            first = cell
        end if
        do k = 1, 3
            call gimp_weight((xi - real(first + k - 1, wp))*dx, lpc, dx, w(k), dw(k))
        end do
    end subroutine gimp_weights_1d

    pure subroutine gimp_shape_weights_1d(self, xi, lp, dx, ncells, first, w, dw)
        class(gimp_shape_type), intent(in) :: self
        real(wp), intent(in) :: xi, lp, dx
        integer, intent(in) :: ncells
        integer, intent(out) :: first
        real(wp), intent(out) :: w(3), dw(3)

        call gimp_weights_1d(xi, lp, dx, ncells, first, w, dw)
    end subroutine gimp_shape_weights_1d

    pure integer function gimp_nodes_per_axis(self)
        class(gimp_shape_type), intent(in) :: self
        gimp_nodes_per_axis = 3
    end function gimp_nodes_per_axis

    subroutine gimp_weights_all(self, grid, x, lp, first, w, dw)
        class(gimp_shape_type), intent(in) :: self
        type(grid_type), intent(in) :: grid
        real(wp), intent(in) :: x(:, :), lp(:, :)
        integer, intent(out) :: first(:, :)
        real(wp), intent(out) :: w(:, :, :), dw(:, :, :)

        integer :: p, a
        real(wp) :: xi, w3(3), dw3(3)

        !$omp parallel do default(none) schedule(static) shared(grid, x, lp, first, w, dw) &
        !$omp private(p, a, xi, w3, dw3)
        do p = 1, size(x, 2)
            do a = 1, grid%dim
                xi = (x(a, p) - grid%origin(a))/grid%dx
                call gimp_weights_1d(xi, lp(a, p), grid%dx, grid%ncells(a), first(a, p), w3, dw3)
                w(:, a, p) = w3(1:3)
                dw(:, a, p) = dw3(1:3)
            end do
        end do
        !$omp end parallel do
    end subroutine gimp_weights_all

end module mpm_shape_gimp
