!> The convected particle domain interpolation (CPDI) of Sadeghirad, Brannon and Burghardt
!> (2011), CPDI1, the domain a parallelogram (2D) or parallelepiped (3D) that follows F.
!>
!> The domain of particle p is the image under F of its initial box: edges r_a = F e_a lp0_a
!> (a = 1 .. dim, lp0 the half-sizes), corners x_c = x_p + sum_a s_ca r_a with the signs
!> s_c in {-1, 1}^dim. The weight of node i and its gradient are those of the linear hat S_i
!> interpolated multilinearly from the corners over the domain, averaged over it:
!>
!>     N_ip      = 2^-dim sum_c S_i(x_c)
!>     grad N_ip = 2^-dim sum_c S_i(x_c) R^-T s_c,     R = (r_1 .. r_dim) = F diag(lp0)
!>
!> (the mean over the domain of the gradient of the interpolant; for a parallelogram the
!> mean of the gradient of the shape function of corner c is 2^-dim R^-T s_c). The weights
!> sum to one, the gradients to zero, and both reproduce linear fields exactly,
!> sum_i N_ip x_i = x_p and sum_i grad N_ip x_i^T = I, at any stretch and rotation. A
!> domain that turns keeps its size (the cpGIMP box of mpm_shape_gimp only approximates a
!> turned domain by a box along the axes), and a particle stretched to a cell or more keeps
!> its nodes: its corners, not its centre, say which nodes it touches, which is what keeps
!> 2 x 2 particles per cell from parting where a beam bends sharply (the clamped root of the
!> cantilever, docs/accuracy-vs-cost.md).
!>
!> A corner outside the grid (the domain of a particle on a face of the grid reaching past
!> it as the particle turns) takes its hat on the node beyond the face linearly extrapolated
!> from the two inside it, S_-1 folded onto S_0 twice and S_1 minus once
!> (mpm_shape::fold_ghost_nodes, as the B-splines): the partition of unity and the linear
!> reproduction hold there too; a corner is taken at most one cell beyond the grid.
!>
!> The stencil is a box of 4 nodes per axis, so the domain may span up to 2 cells along each
!> axis (4 nodes: corners in three consecutive cells); a particle stretched further stops
!> the run (exit 3) with its number and stretch, as CPDI1 has no rule to split it.
module mpm_shape_cpdi
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    use mpm_shape, only: full_shape_type, shape_name_width
    implicit none
    private
    public :: cpdi_shape_type, cpdi_corner_hat, cpdi_gradient_factors

    integer, parameter :: width = 4
        !! nodes per axis of the box: a domain may span up to two cells along an axis

    !> Weights of the convected parallelogram / parallelepiped domain (CPDI1).
    type, extends(full_shape_type) :: cpdi_shape_type
    contains
        procedure :: weights_1d => cpdi_weights_1d
        procedure :: nodes_per_axis => cpdi_nodes_per_axis
        procedure :: halo_width => cpdi_halo_width
        procedure :: names => cpdi_names
        procedure :: weights_full => cpdi_weights_full
    end type cpdi_shape_type

contains

    !> The linear hat weights at a corner xc (in cell units, taken within [-1, ncells + 1]) of
    !> nodes lo .. lo + n - 1 (0-based), the node beyond a grid end folded onto the two inside
    !> (u_-1 = 2 u_0 - u_1). `fits` is false when a nonzero weight falls outside lo .. lo + n - 1.
    pure subroutine cpdi_corner_hat(xc, ncells, lo, n, h, fits)
        real(wp), intent(in) :: xc
            !! corner coordinate in cell units from the grid origin [-]
        integer, intent(in) :: ncells
            !! cells along the axis
        integer, intent(in) :: lo
            !! first node of the box (0-based)
        integer, intent(in) :: n
            !! nodes of the box
        real(wp), intent(out) :: h(n)
            !! hat weights of the box's nodes [-]
        logical, intent(inout) :: fits
            !! set to false when a weight misses the box

        integer :: cell, t, m, node(4), k
        real(wp) :: x, r, v(2), val(4)

        h = 0.0_wp
        x = min(max(xc, -1.0_wp), real(ncells + 1, wp))
        cell = min(max(floor(x), -1), ncells)
        r = x - real(cell, wp)
        v = [1.0_wp - r, r]
        ! the two hat weights, a node beyond an end folded onto the two inside it
        m = 0
        do t = 1, 2
            if (v(t) == 0.0_wp) cycle
            if (cell + t - 1 == -1) then
                node(m + 1:m + 2) = [0, 1]
                val(m + 1:m + 2) = [2.0_wp*v(t), -v(t)]
                m = m + 2
            else if (cell + t - 1 == ncells + 1) then
                node(m + 1:m + 2) = [ncells, ncells - 1]
                val(m + 1:m + 2) = [2.0_wp*v(t), -v(t)]
                m = m + 2
            else
                node(m + 1) = cell + t - 1
                val(m + 1) = v(t)
                m = m + 1
            end if
        end do
        do t = 1, m
            k = node(t) - lo + 1
            if (k < 1 .or. k > n) then
                fits = .false.
            else
                h(k) = h(k) + val(t)
            end if
        end do
    end subroutine cpdi_corner_hat

    !> The gradient factor of each corner, 2^-dim R^-T s_c (R = F diag(lp0)), and det F.
    !> Corner c (1 .. 2^dim) has sign s_ca = -1 when bit a - 1 of c - 1 is clear, +1 when set.
    pure subroutine cpdi_gradient_factors(dim, f, lp0, g, det)
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(in) :: f(dim, dim)
            !! deformation gradient [-]
        real(wp), intent(in) :: lp0(dim)
            !! initial half-sizes [m]
        real(wp), intent(out) :: g(3, 8)
            !! gradient factors of the corners (first dim components of the first 2^dim
            !! corners) [1/m]
        real(wp), intent(out) :: det
            !! det F; the factors are zero when it is not positive

        real(wp) :: cof(dim, dim), s(dim)
        integer :: c, a

        if (dim == 2) then
            det = f(1, 1)*f(2, 2) - f(1, 2)*f(2, 1)
            cof(1, 1) = f(2, 2)
            cof(1, 2) = -f(2, 1)
            cof(2, 1) = -f(1, 2)
            cof(2, 2) = f(1, 1)
        else
            cof(1, 1) = f(2, 2)*f(3, 3) - f(2, 3)*f(3, 2)
            cof(1, 2) = f(2, 3)*f(3, 1) - f(2, 1)*f(3, 3)
            cof(1, 3) = f(2, 1)*f(3, 2) - f(2, 2)*f(3, 1)
            cof(2, 1) = f(1, 3)*f(3, 2) - f(1, 2)*f(3, 3)
            cof(2, 2) = f(1, 1)*f(3, 3) - f(1, 3)*f(3, 1)
            cof(2, 3) = f(1, 2)*f(3, 1) - f(1, 1)*f(3, 2)
            cof(3, 1) = f(1, 2)*f(2, 3) - f(1, 3)*f(2, 2)
            cof(3, 2) = f(1, 3)*f(2, 1) - f(1, 1)*f(2, 3)
            cof(3, 3) = f(1, 1)*f(2, 2) - f(1, 2)*f(2, 1)
            det = f(1, 1)*cof(1, 1) + f(1, 2)*cof(1, 2) + f(1, 3)*cof(1, 3)
        end if
        if (det <= 0.0_wp) then
            g = 0.0_wp
            return
        end if
        ! F^-T = cof(F) / det F
        do c = 1, 2**dim
            do a = 1, dim
                s(a) = merge(1.0_wp, -1.0_wp, btest(c - 1, a - 1))/lp0(a)
            end do
            g(1:dim, c) = matmul(cof, s)/(det*real(2**dim, wp))
        end do
    end subroutine cpdi_gradient_factors

    !> The weights and gradients of the box of every particle (see the module).
    subroutine cpdi_weights_full(self, grid, x, f, lp0, nper, first, w, dw, bad)
        class(cpdi_shape_type), intent(in) :: self
            !! the shape function
        type(grid_type), intent(in) :: grid
            !! grid geometry
        real(wp), intent(in) :: x(:, :)
            !! particle positions (dim, n) [m]
        real(wp), intent(in) :: f(:, :, :)
            !! deformation gradients (dim, dim, n) [-]
        real(wp), intent(in) :: lp0(:, :)
            !! half-sizes of the initial domains (dim, n) [m]
        integer, intent(in) :: nper(3)
            !! nodes of the box per axis (1 on axis 3 in 2D)
        integer, intent(out) :: first(:, :)
            !! first node of the box per axis, 0-based (dim, n)
        real(wp), intent(out) :: w(:, :)
            !! weights (product(nper), n) [-]
        real(wp), intent(out) :: dw(:, :, :)
            !! gradients (dim, product(nper), n) [1/m]
        integer, intent(out) :: bad
            !! first particle whose domain does not fit its box, 0 if none

        integer :: p, dim, nc, c, a, i, j, k, q, lo(3), cell, bad_p, ii, jj, kk, nx, ny, nz, &
            ix(width), iy(width), iz(width)
        real(wp) :: xc(3, 8), g(3, 8), det, lo_x, hi_x, inv_dx, weight, hx(width), hy(width), &
            hz(width), wc
        logical :: fits

        dim = grid%dim
        nc = 2**dim
        inv_dx = 1.0_wp/grid%dx
        wc = 1.0_wp/real(nc, wp)
        bad_p = huge(1)
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(grid, x, f, lp0, nper, first, w, dw, dim, nc, inv_dx, wc) &
        !$omp private(p, c, a, i, j, k, q, lo, cell, xc, g, det, lo_x, hi_x, weight, hx, hy, hz, &
        !$omp fits, ii, jj, kk, nx, ny, nz, ix, iy, iz) reduction(min: bad_p)
        do p = 1, size(x, 2)
            call cpdi_gradient_factors(dim, f(:, :, p), lp0(:, p), g, det)
            fits = det > 0.0_wp
            ! the corners in cell units from the origin
            do c = 1, nc
                do a = 1, dim
                    xc(a, c) = x(a, p)
                end do
                do a = 1, dim
                    xc(1:dim, c) = xc(1:dim, c) + merge(1.0_wp, -1.0_wp, btest(c - 1, a - 1)) &
                        *lp0(a, p)*f(1:dim, a, p)
                end do
                xc(1:dim, c) = (xc(1:dim, c) - grid%origin(1:dim))*inv_dx
            end do
            ! the box: from the node of the lowest corner's cell (0 when a corner lies
            ! beyond the lower end: its fold reaches nodes 0 and 1), kept inside the grid
            lo = 0
            do a = 1, dim
                lo_x = max(minval(xc(a, 1:nc)), -1.0_wp)
                hi_x = min(maxval(xc(a, 1:nc)), real(grid%ncells(a) + 1, wp))
                cell = min(max(floor(lo_x), 0), grid%ncells(a) - 1)
                if (hi_x > real(grid%ncells(a), wp)) cell = min(cell, grid%ncells(a) - 1)
                lo(a) = max(0, min(cell, grid%nn(a) - nper(a)))
                first(a, p) = lo(a)
            end do
            w(:, p) = 0.0_wp
            dw(:, :, p) = 0.0_wp
            hz(1) = 1.0_wp
            do c = 1, nc
                call cpdi_corner_hat(xc(1, c), grid%ncells(1), lo(1), nper(1), hx(1:nper(1)), &
                    fits)
                call cpdi_corner_hat(xc(2, c), grid%ncells(2), lo(2), nper(2), hy(1:nper(2)), &
                    fits)
                if (dim == 3) call cpdi_corner_hat(xc(3, c), grid%ncells(3), lo(3), nper(3), &
                    hz(1:nper(3)), fits)
                ! a corner's hat is nonzero on at most 3 nodes per axis (2, or 3 with a fold):
                ! only those products are formed (each node of the box takes one term per
                ! corner, in corner order, as over the whole box)
                call nonzero(hx(1:nper(1)), ix, nx)
                call nonzero(hy(1:nper(2)), iy, ny)
                call nonzero(hz(1:nper(3)), iz, nz)
                do kk = 1, nz
                    k = iz(kk)
                    do jj = 1, ny
                        j = iy(jj)
                        do ii = 1, nx
                            i = ix(ii)
                            q = i + nper(1)*((j - 1) + nper(2)*(k - 1))
                            weight = hx(i)*hy(j)*hz(k)
                            if (weight == 0.0_wp) cycle
                            w(q, p) = w(q, p) + wc*weight
                            dw(1:dim, q, p) = dw(1:dim, q, p) + weight*g(1:dim, c)
                        end do
                    end do
                end do
            end do
            if (.not. fits) bad_p = min(bad_p, p)
        end do
        !$omp end parallel do
        bad = 0
        if (bad_p /= huge(1)) bad = bad_p
    end subroutine cpdi_weights_full

    !> The positions k of the nonzero entries of h, in order, and their count.
    pure subroutine nonzero(h, index, count)
        real(wp), intent(in) :: h(:)
            !! weights
        integer, intent(out) :: index(:)
            !! positions of the nonzero ones (first count)
        integer, intent(out) :: count
            !! how many
        integer :: k
        count = 0
        do k = 1, size(h)
            if (h(k) /= 0.0_wp) then
                count = count + 1
                index(count) = k
            end if
        end do
    end subroutine nonzero

    !> The weights of a domain along the axes, half-size lp (F diagonal): along an axis the
    !> mean of the hats at the two corners, N = (S(x - lp) + S(x + lp)) / 2, and the mean of
    !> the slope of their interpolant, (S(x + lp) - S(x - lp)) / (2 lp), of the 4 nodes from
    !> the node of the lower corner's cell. 2D and 3D weights are their tensor products.
    pure subroutine cpdi_weights_1d(self, xi, lp, dx, ncells, first, w, dw)
        class(cpdi_shape_type), intent(in) :: self
            !! the shape function
        real(wp), intent(in) :: xi
            !! particle coordinate in cell units, (x - origin) / dx [-]
        real(wp), intent(in) :: lp
            !! particle half-size [m]
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: ncells
            !! cells along this axis
        integer, intent(out) :: first
            !! first node (0-based)
        real(wp), intent(out), contiguous :: w(:)
            !! weights of the 4 nodes [-]
        real(wp), intent(out), contiguous :: dw(:)
            !! derivatives [1/m]

        real(wp) :: xa, xb, ha(width), hb(width)
        logical :: fits

        xa = max(xi - lp/dx, -1.0_wp)
        xb = min(xi + lp/dx, real(ncells + 1, wp))
        first = min(max(floor(xa), 0), ncells - 1)
        if (xb > real(ncells, wp)) first = min(first, ncells - 1)
        first = max(0, min(first, ncells + 1 - width))
        fits = .true.
        call cpdi_corner_hat(xi - lp/dx, ncells, first, width, ha, fits)
        call cpdi_corner_hat(xi + lp/dx, ncells, first, width, hb, fits)
        w(1:width) = 0.5_wp*(ha + hb)
        dw(1:width) = (hb - ha)/(2.0_wp*lp)
    end subroutine cpdi_weights_1d

    pure integer function cpdi_nodes_per_axis(self)
        class(cpdi_shape_type), intent(in) :: self
        cpdi_nodes_per_axis = width
    end function cpdi_nodes_per_axis

    !> Three node layers at a cut, as the cubic B-spline: the box of a particle reaches at
    !> most two nodes beyond its cell's left node.
    pure integer function cpdi_halo_width(self)
        class(cpdi_shape_type), intent(in) :: self
        cpdi_halo_width = 3
    end function cpdi_halo_width

    pure subroutine cpdi_names(self, names)
        class(cpdi_shape_type), intent(in) :: self
        character(len=shape_name_width), allocatable, intent(out) :: names(:)
        names = [character(len=shape_name_width) :: "cpdi", "cpdi1"]
    end subroutine cpdi_names

end module mpm_shape_cpdi
