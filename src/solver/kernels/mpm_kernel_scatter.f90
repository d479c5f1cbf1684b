!> The scatter kernel: one particle's share of mass, momentum, internal force and extra body
!> force to the nodes of its stencil, summed into a chunk buffer (P2G, the MUSL remap).
!>
!> The body (mpm_kernel_scatter.inc) is compiled once per stencil width that has loops of
!> constant length (widths 2 and 3, in 2D and 3D: the compiler unrolls them) and once for any
!> width (`scatter_narrow` for the stencils of widths up to 3 on a grid with an axis of fewer
!> nodes, `scatter_any` for wider ones). The variant is chosen by the width the shape function
!> declares and every axis keeps (`stencils_type%width`), never by counting nodes. The kernel sees the
!> stencils, the grid geometry as numbers (APIC: origin and cell size), the particle's values
!> and the buffer: no grid, particles, case, I/O or coarrays.
module mpm_kernel_scatter
    use mpm_kinds, only: wp
    use mpm_stencil, only: stencils_type, axis_derivatives, fixed_width
    implicit none
    private
    public :: scatter_particle, narrow_width

    integer, parameter :: narrow_width = fixed_width
        !! widest shape function whose stencils on a grid with a narrow axis (fewer nodes than
        !! the width) take the variant with scratch of this fixed width (the vibrating bar,
        !! the columns: one cell across); wider ones take the variant of any width

contains

    !> Add particle p's share to the buffer rows of the nodes of its stencil: mass m N_i and
    !> momentum m N_i (v_p + C_p (x_i - x_p)) from mass_row (or the momentum alone from
    !> momentum_row), the internal force - V_p sigma_p . grad N_i from fint_row, the extra body
    !> force m N_i b_p from body_row (a row 0: not scattered).
    pure subroutine scatter_particle(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
            momentum_row, vs, fint_row, bf, body_row, buf)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        real(wp), intent(in) :: origin(3)
            !! position of node (0, 0, 0) [m] (APIC)
        real(wp), intent(in) :: dx
            !! cell size [m] (APIC)
        integer, intent(in) :: p
            !! particle
        integer, intent(in) :: shift
            !! buffer index of node (x, y, z) minus 1 + x + bstride(2) y + bstride(3) z
            !! (stc%chunk_base of the chunk)
        real(wp), intent(in) :: m
            !! particle mass [kg]
        real(wp), intent(in) :: xp(3)
            !! particle position [m] (APIC)
        real(wp), intent(in) :: vp(3)
            !! particle velocity [m/s]
        real(wp), intent(in) :: aff(3, 3)
            !! affine velocity C_p [1/s] (APIC)
        logical, intent(in) :: apic
            !! add C_p (x_i - x_p) to the node velocity
        integer, intent(in) :: mass_row
            !! 1: mass in row 1 and momentum in rows 2 : 1 + dim; 0: no mass
        integer, intent(in) :: momentum_row
            !! without mass: 1 for the momentum in rows 1 : dim, 0 for none
        real(wp), intent(in) :: vs(6)
            !! - V_p sigma_p (Voigt) [N m]
        integer, intent(in) :: fint_row
            !! first row of the internal force, 0 for none
        real(wp), intent(in) :: bf(3)
            !! extra body force per unit mass [m/s2]
        integer, intent(in) :: body_row
            !! first row of the extra body force, 0 for none
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)

        ! the variant of the stencils' width (0: an axis keeps fewer nodes) and dimension
        select case (10*stc%width + stc%dim)
        case (33)
            call scatter_w3_3d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, vs, &
                fint_row, bf, body_row, buf)
        case (32)
            call scatter_w3_2d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, vs, &
                fint_row, bf, body_row, buf)
        case (23)
            call scatter_w2_3d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, vs, &
                fint_row, bf, body_row, buf)
        case (22)
            call scatter_w2_2d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, vs, &
                fint_row, bf, body_row, buf)
        case default
            if (.not. stc%tensor) then
                call scatter_full(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
                    momentum_row, vs, fint_row, bf, body_row, buf)
            else if (stc%nps <= narrow_width) then
                call scatter_narrow(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
                    momentum_row, vs, fint_row, bf, body_row, buf, stc%nper(1), stc%nper(2), &
                    stc%nper(3))
            else
                call scatter_any(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
                    momentum_row, vs, fint_row, bf, body_row, buf, stc%nper(1), stc%nper(2), &
                    stc%nper(3), stc%nper(1), stc%nper(2), stc%nper(3))
            end if
        end select
    end subroutine scatter_particle

    !> scatter_particle for full stencils of width 3 in 3D.
    pure subroutine scatter_w3_3d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        integer, parameter :: n1 = 3, n2 = 3, n3 = 3
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_w3_3d

    !> scatter_particle for full stencils of width 3 in 2D.
    pure subroutine scatter_w3_2d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        integer, parameter :: n1 = 3, n2 = 3, n3 = 1
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_w3_2d

    !> scatter_particle for full stencils of width 2 in 3D.
    pure subroutine scatter_w2_3d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        integer, parameter :: n1 = 2, n2 = 2, n3 = 2
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_w2_3d

    !> scatter_particle for full stencils of width 2 in 2D.
    pure subroutine scatter_w2_2d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        integer, parameter :: n1 = 2, n2 = 2, n3 = 1
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_w2_2d

    !> scatter_particle for the stencils of a shape function of width up to narrow_width on a
    !> grid with an axis of fewer nodes (n1, n2, n3 <= narrow_width; scratch of that width).
    pure subroutine scatter_narrow(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
            momentum_row, vs, fint_row, bf, body_row, buf, n1, n2, n3)
        integer, intent(in) :: n1, n2, n3
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), intent(inout) :: buf(:, :)
            !! buffer (rows, nodes)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_narrow

    !> scatter_particle for any stencil (a shape function wider than narrow_width without
    !> loops of its width here; scratch of the stencil's width, m = n).
    pure subroutine scatter_any(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf, n1, n2, n3, m1, m2, m3)
        use mpm_stencil, only: axis_derivatives => axis_derivatives_any
        integer, intent(in) :: n1, n2, n3, m1, m2, m3
        real(wp), intent(inout) :: buf(:, :)
            !! buffer (rows, nodes)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_any

    !> scatter_particle for a stencil that is no tensor product (CPDI): the weight and the
    !> gradient of every node of the box from stc%wn and stc%dwn.
    pure subroutine scatter_full(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
            momentum_row, vs, fint_row, bf, body_row, buf)
        type(stencils_type), intent(in) :: stc
        real(wp), intent(in) :: origin(3), dx
        integer, intent(in) :: p, shift
        real(wp), intent(in) :: m, xp(3), vp(3), aff(3, 3)
        logical, intent(in) :: apic
        integer, intent(in) :: mass_row, momentum_row
        real(wp), intent(in) :: vs(6)
        integer, intent(in) :: fint_row
        real(wp), intent(in) :: bf(3)
        integer, intent(in) :: body_row
        real(wp), intent(inout) :: buf(:, :)
            !! buffer (rows, nodes)

        integer :: i, j, k, q, id, dim, f, b
        real(wp) :: wq, mw, g(3), vn(3), r(3), fq(3)

        dim = stc%dim
        f = fint_row
        b = body_row
        g = 0.0_wp
        r = 0.0_wp
        q = 0
        do k = 1, stc%nper(3)
            do j = 1, stc%nper(2)
                id = shift + 1 + stc%first(1, p) + stc%bstride(2)*(stc%first(2, p) + j - 1)
                if (dim == 3) id = id + stc%bstride(3)*(stc%first(3, p) + k - 1)
                do i = 1, stc%nper(1)
                    q = q + 1
                    wq = stc%wn(q, p)
                    g(1:dim) = stc%dwn(:, q, p)
                    mw = m*wq
                    vn = vp
                    if (apic) then
                        r(1) = origin(1) + dx*real(stc%first(1, p) + i - 1, wp) - xp(1)
                        r(2) = origin(2) + dx*real(stc%first(2, p) + j - 1, wp) - xp(2)
                        if (dim == 3) r(3) = origin(3) + dx*real(stc%first(3, p) + k - 1, wp) &
                            - xp(3)
                        vn = vn + matmul(aff, r)
                    end if
                    if (mass_row > 0) then
                        buf(1, id) = buf(1, id) + mw
                        buf(2:1 + dim, id) = buf(2:1 + dim, id) + mw*vn(1:dim)
                    else if (momentum_row > 0) then
                        buf(1:dim, id) = buf(1:dim, id) + mw*vn(1:dim)
                    end if
                    if (f > 0) then
                        ! - V sigma . grad N_i (vs = - V sigma, Voigt xx yy zz xy yz xz)
                        if (dim == 2) then
                            fq(1) = vs(1)*g(1) + vs(4)*g(2)
                            fq(2) = vs(4)*g(1) + vs(2)*g(2)
                        else
                            fq(1) = vs(1)*g(1) + vs(4)*g(2) + vs(6)*g(3)
                            fq(2) = vs(4)*g(1) + vs(2)*g(2) + vs(5)*g(3)
                            fq(3) = vs(6)*g(1) + vs(5)*g(2) + vs(3)*g(3)
                        end if
                        buf(f:f + dim - 1, id) = buf(f:f + dim - 1, id) + fq(1:dim)
                    end if
                    if (b > 0) buf(b:b + dim - 1, id) = buf(b:b + dim - 1, id) + mw*bf(1:dim)
                    id = id + 1
                end do
            end do
        end do
    end subroutine scatter_full

    !> APIC: the parts C_p(:, a) (x_i,a - x_p,a) of the node velocity, per axis and node.
    pure subroutine apic_terms(stc, origin, dx, p, xp, aff, cx, cy, cz)
        type(stencils_type), intent(in) :: stc
        real(wp), intent(in) :: origin(3), dx
        integer, intent(in) :: p
        real(wp), intent(in) :: xp(3), aff(3, 3)
        real(wp), intent(out) :: cx(:, :), cy(:, :), cz(:, :)
            !! (3, nodes along x, y, z) [m/s]

        integer :: i
        real(wp) :: r

        cx = 0.0_wp
        cy = 0.0_wp
        cz = 0.0_wp
        do i = 1, stc%nper(1)
            r = origin(1) + dx*real(stc%first(1, p) + i - 1, wp) - xp(1)
            cx(:, i) = aff(:, 1)*r
        end do
        do i = 1, stc%nper(2)
            r = origin(2) + dx*real(stc%first(2, p) + i - 1, wp) - xp(2)
            cy(:, i) = aff(:, 2)*r
        end do
        if (stc%dim == 3) then
            do i = 1, stc%nper(3)
                r = origin(3) + dx*real(stc%first(3, p) + i - 1, wp) - xp(3)
                cz(:, i) = aff(:, 3)*r
            end do
        end if
    end subroutine apic_terms

end module mpm_kernel_scatter
