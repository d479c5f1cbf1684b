!> The scatter and gather kernels on the window of a particle's nonzero weights
!> (mpm_stencil::nonzero_windows): cpGIMP stencils of width 3 whose first or last weight is zero
!> (a particle domain inside one cell) run the loops of 2 nodes on that axis. Checked against
!> the same kernels over the whole stencil of 3 nodes per axis (the variant of a grid with a
!> narrow axis, reached by setting the stencils' fast-path width to 0): the nodal sums of a
!> scatter (mass, momentum, internal and body force, with and without APIC, and the momentum
!> alone of the MUSL remap: the variants of these passes, and the variant of any pass) and the
!> gathered values and gradients agree to round-off. The
!> particles mix the lattice positions of 2 per cell (domains that end on nodes: windows of 2,
!> with the zero weight first or last) with positions anywhere, some next to a face, so every
!> window kind is met (counted).
program test_mpm_kernel_windows
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_testing_grid, only: made_up_grid, dims
    use mpm_strings, only: fmt_real, int_text
    use mpm_error, only: error_type
    use mpm_grid, only: grid_type
    use mpm_particles, only: particles_type
    use mpm_shape_gimp, only: gimp_shape_type
    use mpm_stencil, only: stencils_type, compute_stencils
    use mpm_kernel_scatter, only: scatter_particle
    use mpm_kernel_gather, only: gather_particle
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: round_off = 16.0_wp*epsilon(1.0_wp)
        !! the two variants add the same nonzero products; the compiler may fuse them into
        !! other multiply-adds, a few roundings of the largest term apart

    call new_suite(suite, "mpm_kernel_windows")
    call check_windows(2, 3000)
    call check_windows(3, 3000)
    call finish(suite)

contains

    !> n particles on a grid of 7 x 6 (x 5) cells of 0.1 m: every third at a lattice position
    !> of 2 particles per cell, the others anywhere (a quasi-random sweep, some within half a
    !> cell of a face); half-size dx/4.
    subroutine make_particles(particles, grid, n)
        type(particles_type), intent(out) :: particles
        type(grid_type), intent(in) :: grid
        integer, intent(in) :: n

        integer :: p, a, dim, cell
        real(wp) :: t, lp

        dim = grid%dim
        lp = 0.25_wp*grid%dx
        particles%n = n
        particles%dim = dim
        allocate (particles%x(dim, n), particles%lp0(dim, n), particles%f(dim, dim, n))
        do p = 1, n
            do a = 1, dim
                t = modulo(0.6180339887_wp*real(p, wp)*real(a + 1, wp) + 0.31_wp*a, 1.0_wp)
                if (mod(p, 3) == 0) then
                    ! the centre of one of the two sub-cells of a cell along this axis
                    cell = int(t*real(grid%ncells(a), wp))
                    particles%x(a, p) = grid%origin(a) + grid%dx*(real(cell, wp) &
                        + merge(0.25_wp, 0.75_wp, mod(p/3 + a, 2) == 0))
                else
                    if (mod(p, 10) == 1) t = 0.02_wp*t
                    particles%x(a, p) = grid%origin(a) + lp &
                        + (grid%dx*real(grid%ncells(a), wp) - 2.0_wp*lp)*t
                end if
            end do
            particles%lp0(:, p) = lp
            ! undeformed: the domain's half-sizes are lp0
            particles%f(:, :, p) = 0.0_wp
            do a = 1, dim
                particles%f(a, a, p) = 1.0_wp
            end do
        end do
    end subroutine make_particles

    !> Every scatter and gather of the windows against the whole stencils, in one dimension.
    subroutine check_windows(dim, n)
        integer, intent(in) :: dim, n

        type(grid_type) :: grid
        type(particles_type) :: particles
        type(gimp_shape_type) :: gimp
        type(stencils_type) :: stc, whole
        type(error_type), allocatable :: error
        character(len=:), allocatable :: what
        integer :: p, a, k, shift, rows, nbuf, two(3), offset_one(3), mass_row, momentum_row, &
            fint_row, body_row, mode
        real(wp), allocatable :: buf(:, :), ref(:, :), fa(:, :), fv(:, :)
        real(wp) :: vs(6), vp(3), bf(3), aff(3, 3), xp(3), m, worst, scale, t
        real(wp) :: ga(3), gv(3), gg(3, 3), ra(3), rv(3), rg(3, 3), worst_g, scale_g
        logical :: apic
        character(len=*), parameter :: modes(5) = [character(len=32) :: "P2G", "P2G with APIC", &
            "P2G with a body force", "momentum (MUSL remap)", "momentum with APIC"]

        what = "cpGIMP "//dims(dim)//": "
        call made_up_grid(grid, dim, [7, 6, 5], 0.1_wp, [1.0_wp, -2.0_wp, 0.5_wp])
        call make_particles(particles, grid, n)
        call compute_stencils(stc, grid, particles, gimp, error)
        call check(suite, .not. allocated(error), what//"stencils computed")
        if (allocated(error)) return
        call check(suite, stc%width == 3 .and. allocated(stc%window), &
            what//"width-3 stencils carry windows")
        if (.not. allocated(stc%window)) return
        whole = stc
        whole%width = 0   ! the variant over all 3 nodes per axis

        ! every window kind is met: per axis 2 nodes with the zero weight last and first
        two = 0
        offset_one = 0
        do p = 1, n
            do a = 1, dim
                if (btest(stc%window(p), a - 1)) two(a) = two(a) + 1
                if (btest(stc%window(p), 2 + a)) offset_one(a) = offset_one(a) + 1
            end do
        end do
        call check(suite, all(two(1:dim) > n/10) .and. all(offset_one(1:dim) > n/20) .and. &
            all(two(1:dim) - offset_one(1:dim) > n/20) .and. all(two(1:dim) < n), &
            what//"windows of 2 nodes with the zero weight first and last, and of 3 (2: "// &
            int_text(two(1))//" along x, of them "//int_text(offset_one(1))//" past first)")

        ! scatter: the whole box of nodes as one buffer
        nbuf = product(stc%box_hi(1:dim) - stc%box_lo(1:dim) + 1)
        shift = -(stc%box_lo(1) + stc%bstride(2)*stc%box_lo(2) + stc%bstride(3)*stc%box_lo(3))
        do mode = 1, 5
            apic = mode == 2 .or. mode == 5
            if (mode < 4) then
                mass_row = 1
                momentum_row = 2
                fint_row = 2 + dim
                body_row = 0
                rows = fint_row + dim - 1
                if (mode == 3) then
                    ! a row more: the variant of any pass
                    body_row = fint_row + dim
                    rows = body_row + dim - 1
                end if
            else
                mass_row = 0
                momentum_row = 1
                fint_row = 0
                body_row = 0
                rows = dim
            end if
            allocate (buf(rows, nbuf), ref(rows, nbuf))
            buf = 0.0_wp
            ref = 0.0_wp
            do p = 1, n
                do k = 1, 6
                    vs(k) = cos(1.3_wp*p + 0.7_wp*k)*1.0e3_wp
                end do
                do k = 1, 3
                    vp(k) = sin(0.9_wp*p + k)
                    bf(k) = cos(0.4_wp*p - k)
                    aff(:, k) = [sin(0.3_wp*p + k), cos(0.5_wp*p - k), sin(0.7_wp*p*k)]*10.0_wp
                end do
                m = 1.0_wp + 0.5_wp*sin(real(p, wp))
                xp = 0.0_wp
                xp(1:dim) = particles%x(:, p)
                call scatter_particle(stc, grid%origin, grid%dx, p, shift, m, xp, vp, aff, apic, &
                    mass_row, momentum_row, vs, fint_row, bf, body_row, buf)
                call scatter_particle(whole, grid%origin, grid%dx, p, shift, m, xp, vp, aff, &
                    apic, mass_row, momentum_row, vs, fint_row, bf, body_row, ref)
            end do
            worst = 0.0_wp
            do k = 1, rows
                scale = max(maxval(abs(ref(k, :))), tiny(1.0_wp))
                worst = max(worst, maxval(abs(buf(k, :) - ref(k, :)))/scale)
            end do
            call check(suite, worst <= round_off, what//"scatter, "//trim(modes(mode))// &
                ": the windows give the sums of the whole stencils (worst "//fmt_real(worst)// &
                " of a row's largest)")
            deallocate (buf, ref)
        end do

        ! gather: two fields and the gradient
        allocate (fa(dim, grid%nnodes), fv(dim, grid%nnodes))
        do k = 1, grid%nnodes
            do a = 1, dim
                t = real(k, wp)*0.37_wp + a
                fa(a, k) = sin(t)
                fv(a, k) = cos(1.7_wp*t)
            end do
        end do
        worst = 0.0_wp
        worst_g = 0.0_wp
        scale = 0.0_wp
        scale_g = 0.0_wp
        do p = 1, n
            call gather_particle(stc, p, fa, fv, .true., .true., .true., ga, gv, gg)
            call gather_particle(whole, p, fa, fv, .true., .true., .true., ra, rv, rg)
            worst = max(worst, maxval(abs(ga(1:dim) - ra(1:dim))), &
                maxval(abs(gv(1:dim) - rv(1:dim))))
            worst_g = max(worst_g, maxval(abs(gg(1:dim, 1:dim) - rg(1:dim, 1:dim))))
            scale = max(scale, maxval(abs(ra(1:dim))), maxval(abs(rv(1:dim))))
            scale_g = max(scale_g, maxval(abs(rg(1:dim, 1:dim))))
        end do
        call check(suite, worst <= round_off*scale .and. worst_g <= round_off*scale_g, &
            what//"gather: the windows give the values and gradients of the whole stencils "// &
            "(worst "//fmt_real(worst/scale)//", gradient "//fmt_real(worst_g/scale_g)//")")
    end subroutine check_windows

end program test_mpm_kernel_windows
