!> The gather kernel: two nodal vector fields (and the gradient of one) at a particle, from
!> the nodes of its stencil (G2P, stress update).
!>
!> As the scatter kernel (mpm_kernel_scatter), the body (mpm_kernel_gather.inc) is compiled
!> once per stencil width with loops of constant length (2 and 3, in 2D and 3D), once for the
!> narrow grids of widths up to 3 and once for any width, and the variant is chosen by
!> `stencils_type%width`.
module mpm_kernel_gather
    use mpm_kinds, only: wp
    use mpm_stencil, only: stencils_type, axis_derivatives, fixed_width
    use mpm_kernel_scatter, only: narrow_width
    implicit none
    private
    public :: gather_particle

contains

    !> Gather at one particle from two nodal vector fields: sum N_i fa_i, sum N_i fv_i and,
    !> when `with_gradient`, sum fv_i (x) grad N_i (gradient(i, j) = d fv_i / d x_j).
    pure subroutine gather_particle(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: p
            !! particle
        real(wp), intent(in), contiguous :: fa(:, :), fv(:, :)
            !! nodal fields (dim, nodes): acceleration and velocity
        logical, intent(in) :: with_a, with_v, with_gradient
            !! gather fa; gather fv; gather the gradient of fv
        real(wp), intent(out) :: a(3), v(3), gradient(3, 3)
            !! results (first dim components; v is zero without with_v and with_gradient)

        ! the variant of the stencils' width (0: an axis keeps fewer nodes) and dimension
        select case (10*stc%width + stc%dim)
        case (33)
            call gather_w3_3d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case (32)
            call gather_w3_2d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case (23)
            call gather_w2_3d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case (22)
            call gather_w2_2d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case default
            if (.not. stc%tensor) then
                call gather_full(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
            else if (stc%nps <= narrow_width) then
                call gather_narrow(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
                    stc%nper(1), stc%nper(2), stc%nper(3))
            else
                call gather_any(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
                    stc%nper(1), stc%nper(2), stc%nper(3), stc%nper(1), stc%nper(2), stc%nper(3))
            end if
        end select
    end subroutine gather_particle

    !> gather_particle for full stencils of width 3 in 3D.
    pure subroutine gather_w3_3d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! the nodal fields by address: no descriptors per particle (explicit extents changed
        ! the inlining and the last bits of two cases)
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        integer, parameter :: n1 = 3, n2 = 3, n3 = 3
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_w3_3d

    !> gather_particle for full stencils of width 3 in 2D.
    pure subroutine gather_w3_2d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! the nodal fields by address: no descriptors per particle (explicit extents changed
        ! the inlining and the last bits of two cases)
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        integer, parameter :: n1 = 3, n2 = 3, n3 = 1
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_w3_2d

    !> gather_particle for full stencils of width 2 in 3D.
    pure subroutine gather_w2_3d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! the nodal fields by address: no descriptors per particle (explicit extents changed
        ! the inlining and the last bits of two cases)
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        integer, parameter :: n1 = 2, n2 = 2, n3 = 2
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_w2_3d

    !> gather_particle for full stencils of width 2 in 2D.
    pure subroutine gather_w2_2d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! the nodal fields by address: no descriptors per particle (explicit extents changed
        ! the inlining and the last bits of two cases)
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        integer, parameter :: n1 = 2, n2 = 2, n3 = 1
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_w2_2d

    !> gather_particle for the stencils of a shape function of width up to narrow_width on a
    !> grid with an axis of fewer nodes (scratch of that width).
    pure subroutine gather_narrow(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
            n1, n2, n3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: n1, n2, n3
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), intent(in), contiguous :: fa(:, :), fv(:, :)
            !! nodal fields (dim, nodes)
        include "mpm_kernel_gather.inc"
    end subroutine gather_narrow

    !> gather_particle for any stencil (a shape function wider than narrow_width without
    !> loops of its width here; scratch of the stencil's width, m = n).
    pure subroutine gather_any(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
            n1, n2, n3, m1, m2, m3)
        use mpm_stencil, only: axis_derivatives => axis_derivatives_any
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: n1, n2, n3, m1, m2, m3
        real(wp), intent(in), contiguous :: fa(:, :), fv(:, :)
            !! nodal fields (dim, nodes)
        include "mpm_kernel_gather.inc"
    end subroutine gather_any

    !> gather_particle for a stencil that is no tensor product (CPDI): the weight and the
    !> gradient of every node of the box from stc%wn and stc%dwn.
    pure subroutine gather_full(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: p
            !! particle
        real(wp), intent(in), contiguous :: fa(:, :), fv(:, :)
            !! nodal fields (dim, nodes)
        logical, intent(in) :: with_a, with_v, with_gradient
            !! gather fa; gather fv; gather the gradient of fv
        real(wp), intent(out) :: a(3), v(3), gradient(3, 3)
            !! results (first dim components)

        integer :: i, j, k, q, id, dim, c
        real(wp) :: wq

        dim = stc%dim
        a = 0.0_wp
        v = 0.0_wp
        gradient = 0.0_wp
        q = 0
        do k = 1, stc%nper(3)
            do j = 1, stc%nper(2)
                id = 1 + stc%first(1, p) + stc%stride(2)*(stc%first(2, p) + j - 1)
                if (dim == 3) id = id + stc%stride(3)*(stc%first(3, p) + k - 1)
                do i = 1, stc%nper(1)
                    q = q + 1
                    wq = stc%wn(q, p)
                    if (with_a) a(1:dim) = a(1:dim) + wq*fa(1:dim, id)
                    if (with_v .or. with_gradient) v(1:dim) = v(1:dim) + wq*fv(1:dim, id)
                    if (with_gradient) then
                        do c = 1, dim
                            gradient(1:dim, c) = gradient(1:dim, c) + fv(1:dim, id)*stc%dwn(c, q, p)
                        end do
                    end if
                    id = id + 1
                end do
            end do
        end do
    end subroutine gather_full

end module mpm_kernel_gather
