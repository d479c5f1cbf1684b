!> The scatter kernel: one particle's share of mass, momentum, internal force and extra body
!> force to the nodes of its stencil, summed into a chunk buffer (P2G, the MUSL remap).
!>
!> The body (mpm_kernel_scatter.inc) is compiled once per case with loops of constant length
!> along x and once for any width. Stencils of width 3 (cpGIMP, uGIMP, quadratic B-splines)
!> run over the window of the particle's nonzero weights (mpm_stencil::nonzero_windows: 2 or 3
!> nodes per axis), in a variant per window length along x (the innermost loop, unrolled) and
!> per pass: P2G and the MUSL remap, with FLIP or APIC, have variants that know what they
!> scatter at compile time (`pass_kind`); any other scatter (a body force, the USF passes,
!> XPIC's map) takes the variant with the rows as arguments. Stencils of width 2 (linear)
!> have their variants of constant length; `scatter_narrow` serves the stencils of widths up
!> to 3 on a grid with an axis of fewer nodes and `scatter_any` wider ones. The variant is
!> chosen by the width the shape function declares and every axis keeps
!> (`stencils_type%width`). The kernel sees the stencils, the grid geometry as numbers (APIC:
!> origin and cell size), the particle's values and the buffer: no grid, particles, case, I/O
!> or coarrays.
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

        integer :: window, n1, n2, n3, o1, o2, o3, pass

        ! the variant of the stencils' width (0: an axis keeps fewer nodes) and dimension; a
        ! width-3 stencil by the window of its nonzero weights (2 or 3 nodes per axis: along x
        ! a variant each, the loops along y and z of runtime length) and by the pass
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
            pass = pass_kind(stc%dim, apic, mass_row, momentum_row, fint_row, body_row)

            if (stc%dim == 3) then
                select case (10*pass + n1)
                case (3)
                    call scatter_rows_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
                        momentum_row, vs, fint_row, bf, body_row, buf, n2, n3, o1, o2, o3)
                case (2)
                    call scatter_rows_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
                        momentum_row, vs, fint_row, bf, body_row, buf, n2, n3, o1, o2, o3)
                case (13)
                    call scatter_p2g_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, n3, o1, o2, o3)
                case (12)
                    call scatter_p2g_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, n3, o1, o2, o3)
                case (23)
                    call scatter_remap_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, n3, o1, o2, o3)
                case (22)
                    call scatter_remap_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, n3, o1, o2, o3)
                case (33)
                    call scatter_p2g_apic_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, n3, o1, o2, o3)
                case (32)
                    call scatter_p2g_apic_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, n3, o1, o2, o3)
                case (43)
                    call scatter_remap_apic_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, n3, o1, o2, o3)
                case default
                    ! 42: the last of an exhaustive list (windows of 2 or 3 nodes, known passes)
                    call scatter_remap_apic_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, n3, o1, o2, o3)
                end select
            else
                select case (10*pass + n1)
                case (3)
                    call scatter_rows_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
                        momentum_row, vs, fint_row, bf, body_row, buf, n2, o1, o2)
                case (2)
                    call scatter_rows_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
                        momentum_row, vs, fint_row, bf, body_row, buf, n2, o1, o2)
                case (13)
                    call scatter_p2g_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, o1, o2)
                case (12)
                    call scatter_p2g_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, o1, o2)
                case (23)
                    call scatter_remap_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, o1, o2)
                case (22)
                    call scatter_remap_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, o1, o2)
                case (33)
                    call scatter_p2g_apic_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, o1, o2)
                case (32)
                    call scatter_p2g_apic_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, o1, o2)
                case (43)
                    call scatter_remap_apic_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, o1, o2)
                case default
                    ! 42: the last of an exhaustive list (windows of 2 or 3 nodes, known passes)
                    call scatter_remap_apic_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, &
                        n2, o1, o2)
                end select
            end if
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
                    stc%nper(3), stc%nper(1), stc%nper(2), stc%nper(3))
            else
                call scatter_any(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
                    momentum_row, vs, fint_row, bf, body_row, buf, stc%nper(1), stc%nper(2), &
                    stc%nper(3), stc%nper(1), stc%nper(2), stc%nper(3), stc%nper(1), stc%nper(2), &
                    stc%nper(3))
            end if
        end select
    end subroutine scatter_particle

    !> scatter_particle for any pass: the window of 3 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_rows_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
            momentum_row, vs, fint_row, bf, body_row, buf, n2, n3, o1, o2, o3)
        include "mpm_kernel_scatter_rows.inc"
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_rows_3d_x3

    !> scatter_particle for any pass: the window of 2 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_rows_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
            momentum_row, vs, fint_row, bf, body_row, buf, n2, n3, o1, o2, o3)
        include "mpm_kernel_scatter_rows.inc"
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_rows_3d_x2

    !> scatter_particle for any pass: the window of 3 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_rows_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
            momentum_row, vs, fint_row, bf, body_row, buf, n2, o1, o2)
        include "mpm_kernel_scatter_rows.inc"
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_rows_2d_x3

    !> scatter_particle for any pass: the window of 2 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_rows_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
            momentum_row, vs, fint_row, bf, body_row, buf, n2, o1, o2)
        include "mpm_kernel_scatter_rows.inc"
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_rows_2d_x2

    !> scatter_particle for P2G (FLIP): the window of 3 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_p2g_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, n3, o1, o2, o3)
        logical, parameter :: apic = .false.
        integer, parameter :: mass_row = 1, momentum_row = 2, fint_row = 5, body_row = 0
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_p2g_3d_x3

    !> scatter_particle for P2G (FLIP): the window of 2 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_p2g_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, n3, o1, o2, o3)
        logical, parameter :: apic = .false.
        integer, parameter :: mass_row = 1, momentum_row = 2, fint_row = 5, body_row = 0
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_p2g_3d_x2

    !> scatter_particle for P2G (FLIP): the window of 3 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_p2g_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, o1, o2)
        logical, parameter :: apic = .false.
        integer, parameter :: mass_row = 1, momentum_row = 2, fint_row = 4, body_row = 0
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_p2g_2d_x3

    !> scatter_particle for P2G (FLIP): the window of 2 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_p2g_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, o1, o2)
        logical, parameter :: apic = .false.
        integer, parameter :: mass_row = 1, momentum_row = 2, fint_row = 4, body_row = 0
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_p2g_2d_x2

    !> scatter_particle for the MUSL remap (FLIP): the window of 3 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_remap_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, n3, o1, o2, o3)
        logical, parameter :: apic = .false.
        integer, parameter :: mass_row = 0, momentum_row = 1, fint_row = 0, body_row = 0
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_remap_3d_x3

    !> scatter_particle for the MUSL remap (FLIP): the window of 2 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_remap_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, n3, o1, o2, o3)
        logical, parameter :: apic = .false.
        integer, parameter :: mass_row = 0, momentum_row = 1, fint_row = 0, body_row = 0
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_remap_3d_x2

    !> scatter_particle for the MUSL remap (FLIP): the window of 3 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_remap_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, o1, o2)
        logical, parameter :: apic = .false.
        integer, parameter :: mass_row = 0, momentum_row = 1, fint_row = 0, body_row = 0
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_remap_2d_x3

    !> scatter_particle for the MUSL remap (FLIP): the window of 2 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_remap_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, o1, o2)
        logical, parameter :: apic = .false.
        integer, parameter :: mass_row = 0, momentum_row = 1, fint_row = 0, body_row = 0
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_remap_2d_x2

    !> scatter_particle for P2G (APIC): the window of 3 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_p2g_apic_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, n3, o1, o2, o3)
        logical, parameter :: apic = .true.
        integer, parameter :: mass_row = 1, momentum_row = 2, fint_row = 5, body_row = 0
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_p2g_apic_3d_x3

    !> scatter_particle for P2G (APIC): the window of 2 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_p2g_apic_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, n3, o1, o2, o3)
        logical, parameter :: apic = .true.
        integer, parameter :: mass_row = 1, momentum_row = 2, fint_row = 5, body_row = 0
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_p2g_apic_3d_x2

    !> scatter_particle for P2G (APIC): the window of 3 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_p2g_apic_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, o1, o2)
        logical, parameter :: apic = .true.
        integer, parameter :: mass_row = 1, momentum_row = 2, fint_row = 4, body_row = 0
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_p2g_apic_2d_x3

    !> scatter_particle for P2G (APIC): the window of 2 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_p2g_apic_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, o1, o2)
        logical, parameter :: apic = .true.
        integer, parameter :: mass_row = 1, momentum_row = 2, fint_row = 4, body_row = 0
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_p2g_apic_2d_x2

    !> scatter_particle for the MUSL remap (APIC): the window of 3 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_remap_apic_3d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, n3, o1, o2, o3)
        logical, parameter :: apic = .true.
        integer, parameter :: mass_row = 0, momentum_row = 1, fint_row = 0, body_row = 0
        integer, parameter :: n1 = 3, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_remap_apic_3d_x3

    !> scatter_particle for the MUSL remap (APIC): the window of 2 nodes along x of a stencil of width 3
    !> in 3D.
    pure subroutine scatter_remap_apic_3d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, n3, o1, o2, o3)
        logical, parameter :: apic = .true.
        integer, parameter :: mass_row = 0, momentum_row = 1, fint_row = 0, body_row = 0
        integer, parameter :: n1 = 2, f1 = 3, f2 = 3, f3 = 3
        integer, intent(in) :: n2, n3, o1, o2, o3
            !! nodes of the window along y and z; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_remap_apic_3d_x2

    !> scatter_particle for the MUSL remap (APIC): the window of 3 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_remap_apic_2d_x3(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, o1, o2)
        logical, parameter :: apic = .true.
        integer, parameter :: mass_row = 0, momentum_row = 1, fint_row = 0, body_row = 0
        integer, parameter :: n1 = 3, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_remap_apic_2d_x3

    !> scatter_particle for the MUSL remap (APIC): the window of 2 nodes along x of a stencil of width 3
    !> in 2D.
    pure subroutine scatter_remap_apic_2d_x2(stc, origin, dx, p, shift, m, xp, vp, aff, vs, bf, buf, n2, o1, o2)
        logical, parameter :: apic = .true.
        integer, parameter :: mass_row = 0, momentum_row = 1, fint_row = 0, body_row = 0
        integer, parameter :: n1 = 2, n3 = 1, f1 = 3, f2 = 3, f3 = 1, o3 = 0
        integer, intent(in) :: n2, o1, o2
            !! nodes of the window along y; its first node per axis past the stencil's
            !! first
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_remap_apic_2d_x2

    !> scatter_particle for full stencils of width 2 in 3D.
    pure subroutine scatter_w2_3d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        include "mpm_kernel_scatter_rows.inc"
        integer, parameter :: n1 = 2, n2 = 2, n3 = 2, f1 = 2, f2 = 2, f3 = 2
        integer, parameter :: o1 = 0, o2 = 0, o3 = 0
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_w2_3d

    !> scatter_particle for full stencils of width 2 in 2D.
    pure subroutine scatter_w2_2d(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        include "mpm_kernel_scatter_rows.inc"
        integer, parameter :: n1 = 2, n2 = 2, n3 = 1, f1 = 2, f2 = 2, f3 = 1
        integer, parameter :: o1 = 0, o2 = 0, o3 = 0
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! buffer (rows, nodes; contiguous: unit stride along the rows of a node)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_w2_2d

    !> scatter_particle for the stencils of a shape function of width up to narrow_width on a
    !> grid with an axis of fewer nodes (n1, n2, n3 <= narrow_width; scratch of that width).
    pure subroutine scatter_narrow(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, &
            momentum_row, vs, fint_row, bf, body_row, buf, n1, n2, n3, f1, f2, f3)
        include "mpm_kernel_scatter_rows.inc"
        integer, intent(in) :: n1, n2, n3, f1, f2, f3
            !! nodes per axis (the window is the whole stencil: f = n)
        integer, parameter :: m1 = fixed_width, m2 = fixed_width, m3 = fixed_width
        integer, parameter :: o1 = 0, o2 = 0, o3 = 0
        real(wp), intent(inout) :: buf(:, :)
            !! buffer (rows, nodes)
        include "mpm_kernel_scatter.inc"
    end subroutine scatter_narrow

    !> scatter_particle for any stencil (a shape function wider than narrow_width without
    !> loops of its width here; scratch of the stencil's width, m = n).
    pure subroutine scatter_any(stc, origin, dx, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf, n1, n2, n3, f1, f2, f3, m1, m2, m3)
        use mpm_stencil, only: axis_derivatives => axis_derivatives_any
        include "mpm_kernel_scatter_rows.inc"
        integer, intent(in) :: n1, n2, n3, f1, f2, f3, m1, m2, m3
            !! nodes per axis (the window is the whole stencil: f = n) and scratch extents
        integer, parameter :: o1 = 0, o2 = 0, o3 = 0
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

    !> Which variant serves a scatter: 1 P2G (mass, momentum and internal force), 2 the MUSL
    !> remap (momentum alone), 3 and 4 the same with APIC, 0 any other (the rows as arguments).
    pure integer function pass_kind(dim, apic, mass_row, momentum_row, fint_row, body_row)
        integer, intent(in) :: dim
            !! space dimensions
        logical, intent(in) :: apic
            !! add C_p (x_i - x_p) to the node velocity
        integer, intent(in) :: mass_row, momentum_row, fint_row, body_row
            !! the rows of the scatter (see scatter_particle)

        pass_kind = 0
        if (body_row /= 0) return
        if (mass_row == 1 .and. momentum_row == 2 .and. fint_row == 2 + dim) then
            pass_kind = merge(3, 1, apic)
        else if (mass_row == 0 .and. momentum_row == 1 .and. fint_row == 0) then
            pass_kind = merge(4, 2, apic)
        end if
    end function pass_kind

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
