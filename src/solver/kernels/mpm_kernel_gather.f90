!> The gather kernel: two nodal vector fields (and the gradient of one) at a particle, from
!> the nodes of its stencil (G2P, stress update).
!>
!> As the scatter kernel (mpm_kernel_scatter), the body (mpm_kernel_gather.inc) is compiled
!> once per case with loops of constant length along x and once for any width. Stencils of
!> width 3 (cpGIMP, uGIMP, quadratic B-splines) run over the window of the particle's nonzero
!> weights (mpm_stencil::nonzero_windows: 2 or 3 nodes per axis), in a variant per window
!> length along x and per pass: the common passes (a and v for G2P, v and its gradient for
!> the stress update, all three for MUSL's G2P, a alone) have variants that know what they
!> gather at compile time; any other takes the variant with the choice as arguments
!> (mpm_kernel_gather_fields.inc). Stencils of width 2 have their variants of constant
!> length, `narrow_width` grids the variant of widths up to 3 and wider stencils the variant
!> of any width. The variant is chosen by `stencils_type%width` and `stencils_type%window`.
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

        integer :: window, n1, n2, n3, o1, o2, o3, pass

        ! the variant of the stencils' width (0: an axis keeps fewer nodes) and dimension; a
        ! width-3 stencil by the window of its nonzero weights (2 or 3 nodes per axis: along x
        ! a variant each, the loops along y and z of runtime length) and by what is gathered
        select case (10*stc%width + stc%dim)
        case (33, 32)
            window = stc%window(p)
            n1 = 3 - ibits(window, 0, 1)
            n2 = 3 - ibits(window, 1, 1)
            n3 = 1
            if (stc%dim == 3) n3 = 3 - ibits(window, 2, 1)
            o1 = ibits(window, 3, 1)
            o2 = ibits(window, 4, 1)
            o3 = ibits(window, 5, 1)
            pass = 0
            if (with_a .and. with_v .and. .not. with_gradient) pass = 1
            if (.not. with_a .and. with_v .and. with_gradient) pass = 2
            if (with_a .and. with_v .and. with_gradient) pass = 3
            if (with_a .and. .not. (with_v .or. with_gradient)) pass = 4

            if (stc%dim == 3) then
                select case (10*pass + n1)
                case (3)
                    call gather_fields_3d_x3(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, &
                        gradient, n2, n3, o1, o2, o3)
                case (2)
                    call gather_fields_3d_x2(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, &
                        gradient, n2, n3, o1, o2, o3)
                case (13)
                    call gather_av_3d_x3(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
                case (12)
                    call gather_av_3d_x2(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
                case (23)
                    call gather_vgrad_3d_x3(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
                case (22)
                    call gather_vgrad_3d_x2(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
                case (33)
                    call gather_avgrad_3d_x3(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
                case (32)
                    call gather_avgrad_3d_x2(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
                case (43)
                    call gather_a_3d_x3(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
                case default
                    ! 42: the last of an exhaustive list (windows of 2 or 3 nodes, known passes)
                    call gather_a_3d_x2(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
                end select
            else
                select case (10*pass + n1)
                case (3)
                    call gather_fields_2d_x3(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, &
                        gradient, n2, o1, o2)
                case (2)
                    call gather_fields_2d_x2(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, &
                        gradient, n2, o1, o2)
                case (13)
                    call gather_av_2d_x3(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
                case (12)
                    call gather_av_2d_x2(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
                case (23)
                    call gather_vgrad_2d_x3(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
                case (22)
                    call gather_vgrad_2d_x2(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
                case (33)
                    call gather_avgrad_2d_x3(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
                case (32)
                    call gather_avgrad_2d_x2(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
                case (43)
                    call gather_a_2d_x3(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
                case default
                    ! 42: the last of an exhaustive list (windows of 2 or 3 nodes, known passes)
                    call gather_a_2d_x2(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
                end select
            end if
        case (23)
            call gather_w2_3d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case (22)
            call gather_w2_2d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case default
            if (.not. stc%tensor) then
                call gather_full(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
            else if (stc%nps <= narrow_width) then
                call gather_narrow(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
                    stc%nper(1), stc%nper(2), stc%nper(3), stc%nper(1), stc%nper(2), stc%nper(3))
            else
                call gather_any(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
                    stc%nper(1), stc%nper(2), stc%nper(3), stc%nper(1), stc%nper(2), stc%nper(3), &
                    stc%nper(1), stc%nper(2), stc%nper(3))
            end if
        end select
    end subroutine gather_particle

    !> gather_particle for any pass: the window of 3 nodes along x of a stencil of
    !> width 3 in 3D.
    pure subroutine gather_fields_3d_x3(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
            n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        include "mpm_kernel_gather_fields.inc"
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_fields_3d_x3

    !> gather_particle for any pass: the window of 2 nodes along x of a stencil of
    !> width 3 in 3D.
    pure subroutine gather_fields_3d_x2(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
            n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        include "mpm_kernel_gather_fields.inc"
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_fields_3d_x2

    !> gather_particle for any pass: the window of 3 nodes along x of a stencil of
    !> width 3 in 2D.
    pure subroutine gather_fields_2d_x3(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
            n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        include "mpm_kernel_gather_fields.inc"
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_fields_2d_x3

    !> gather_particle for any pass: the window of 2 nodes along x of a stencil of
    !> width 3 in 2D.
    pure subroutine gather_fields_2d_x2(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
            n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        include "mpm_kernel_gather_fields.inc"
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_fields_2d_x2

    !> gather_particle for G2P (two fields): the window of 3 nodes along x of a stencil of
    !> width 3 in 3D.
    pure subroutine gather_av_3d_x3(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .true., with_gradient = .false.
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_av_3d_x3

    !> gather_particle for G2P (two fields): the window of 2 nodes along x of a stencil of
    !> width 3 in 3D.
    pure subroutine gather_av_3d_x2(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .true., with_gradient = .false.
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_av_3d_x2

    !> gather_particle for G2P (two fields): the window of 3 nodes along x of a stencil of
    !> width 3 in 2D.
    pure subroutine gather_av_2d_x3(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .true., with_gradient = .false.
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_av_2d_x3

    !> gather_particle for G2P (two fields): the window of 2 nodes along x of a stencil of
    !> width 3 in 2D.
    pure subroutine gather_av_2d_x2(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .true., with_gradient = .false.
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_av_2d_x2

    !> gather_particle for the stress update and APIC's G2P (a field and its gradient): the
    !> window of 3 nodes along x of a stencil of width 3 in 3D.
    pure subroutine gather_vgrad_3d_x3(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .false., with_v = .true., with_gradient = .true.
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_vgrad_3d_x3

    !> gather_particle for the stress update and APIC's G2P (a field and its gradient): the
    !> window of 2 nodes along x of a stencil of width 3 in 3D.
    pure subroutine gather_vgrad_3d_x2(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .false., with_v = .true., with_gradient = .true.
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_vgrad_3d_x2

    !> gather_particle for the stress update and APIC's G2P (a field and its gradient): the
    !> window of 3 nodes along x of a stencil of width 3 in 2D.
    pure subroutine gather_vgrad_2d_x3(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .false., with_v = .true., with_gradient = .true.
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_vgrad_2d_x3

    !> gather_particle for the stress update and APIC's G2P (a field and its gradient): the
    !> window of 2 nodes along x of a stencil of width 3 in 2D.
    pure subroutine gather_vgrad_2d_x2(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .false., with_v = .true., with_gradient = .true.
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_vgrad_2d_x2

    !> gather_particle for USL's G2P with the stress (two fields and a gradient): the window of 3 nodes along x of a stencil of
    !> width 3 in 3D.
    pure subroutine gather_avgrad_3d_x3(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .true., with_gradient = .true.
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_avgrad_3d_x3

    !> gather_particle for USL's G2P with the stress (two fields and a gradient): the window of 2 nodes along x of a stencil of
    !> width 3 in 3D.
    pure subroutine gather_avgrad_3d_x2(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .true., with_gradient = .true.
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_avgrad_3d_x2

    !> gather_particle for USL's G2P with the stress (two fields and a gradient): the window of 3 nodes along x of a stencil of
    !> width 3 in 2D.
    pure subroutine gather_avgrad_2d_x3(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .true., with_gradient = .true.
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_avgrad_2d_x3

    !> gather_particle for USL's G2P with the stress (two fields and a gradient): the window of 2 nodes along x of a stencil of
    !> width 3 in 2D.
    pure subroutine gather_avgrad_2d_x2(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .true., with_gradient = .true.
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_avgrad_2d_x2

    !> gather_particle for FLIP's G2P and XPIC (one field): the window of 3 nodes along x of a
    !> stencil of width 3 in 3D.
    pure subroutine gather_a_3d_x3(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .false., with_gradient = .false.
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_a_3d_x3

    !> gather_particle for FLIP's G2P and XPIC (one field): the window of 2 nodes along x of a
    !> stencil of width 3 in 3D.
    pure subroutine gather_a_3d_x2(stc, p, fa, fv, a, v, gradient, n2, n3, o1, o2, o3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .false., with_gradient = .false.
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_a_3d_x2

    !> gather_particle for FLIP's G2P and XPIC (one field): the window of 3 nodes along x of a
    !> stencil of width 3 in 2D.
    pure subroutine gather_a_2d_x3(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .false., with_gradient = .false.
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_a_2d_x3

    !> gather_particle for FLIP's G2P and XPIC (one field): the window of 2 nodes along x of a
    !> stencil of width 3 in 2D.
    pure subroutine gather_a_2d_x2(stc, p, fa, fv, a, v, gradient, n2, o1, o2)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        logical, parameter :: with_a = .true., with_v = .false., with_gradient = .false.
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_a_2d_x2

    !> gather_particle for full stencils of width 2 in 3D.
    pure subroutine gather_w2_3d(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        ! the nodal fields by address: no descriptors per particle (explicit extents changed
        ! the inlining and the last bits of two cases)
        ! allow(assumed-size): nodal fields passed by address
        real(wp), intent(in) :: fa(stc%dim, *), fv(stc%dim, *)
            !! nodal fields (dim, nodes)
        include "mpm_kernel_gather_fields.inc"
        integer, parameter :: n1 = 2, n2 = 2, n3 = 2, f1 = 2, f2 = 2, f3 = 2
        integer, parameter :: o1 = 0, o2 = 0, o3 = 0
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
        include "mpm_kernel_gather_fields.inc"
        integer, parameter :: n1 = 2, n2 = 2, n3 = 1, f1 = 2, f2 = 2, f3 = 1
        integer, parameter :: o1 = 0, o2 = 0, o3 = 0
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        include "mpm_kernel_gather.inc"
    end subroutine gather_w2_2d

    !> gather_particle for the stencils of a shape function of width up to narrow_width on a
    !> grid with an axis of fewer nodes (scratch of that width).
    pure subroutine gather_narrow(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
            n1, n2, n3, f1, f2, f3)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        include "mpm_kernel_gather_fields.inc"
        integer, intent(in) :: n1, n2, n3, f1, f2, f3
            !! nodes per axis (the window is the whole stencil: f = n)
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        integer, parameter :: o1 = 0, o2 = 0, o3 = 0
        real(wp), intent(in), contiguous :: fa(:, :), fv(:, :)
            !! nodal fields (dim, nodes)
        include "mpm_kernel_gather.inc"
    end subroutine gather_narrow

    !> gather_particle for any stencil (a shape function wider than narrow_width without
    !> loops of its width here; scratch of the stencil's width, m = n).
    pure subroutine gather_any(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
            n1, n2, n3, f1, f2, f3, m1, m2, m3)
        use mpm_stencil, only: axis_derivatives => axis_derivatives_any
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        include "mpm_kernel_gather_fields.inc"
        integer, intent(in) :: n1, n2, n3, f1, f2, f3, m1, m2, m3
            !! nodes per axis (the window is the whole stencil: f = n) and scratch extents
        integer, parameter :: o1 = 0, o2 = 0, o3 = 0
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
