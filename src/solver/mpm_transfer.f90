!> The particle passes of one explicit step: the threaded loops over particles that call the
!> kernels (src/solver/kernels/).
!>
!> Particle-to-grid (P2G) scatters mass, momentum and forces to the nodes (mpm_kernel_scatter);
!> grid-to-particle (G2P) gathers accelerations and velocities back (mpm_kernel_gather); the
!> stress update uses the nodal velocities chosen by the scheme (its kernel for a block of
!> particles: mpm_kernel_stress). The
!> nodal update is mpm_kernel_nodal. Each pass is one procedure; the step (mpm_solver::advance)
!> orders them by the scheme (USF/USL/MUSL) and completes the nodes shared with other images
!> after each scatter (mpm_halo): the passes see no coarrays. USL without F-bar updates the
!> stresses inside G2P (the same nodal velocities, one gather instead of two). Every pass
!> reads the stencils of the step (mpm_stencil): the shape functions are evaluated once per
!> step, and the grid work covers the box of nodes the particles touch.
!>
!> Threads: the gathers (G2P, stress update) are parallel over particles; the scatters (P2G,
!> remap) sum each chunk of cell-sorted particles into its own buffer and fold the buffers
!> into the grid in chunk order; every sum over particles (energies) is taken per chunk or
!> block and the partial sums added in a fixed order. A run gives the same bits with any
!> number of threads.
module mpm_transfer
    use mpm_kinds, only: wp
    use mpm_strings, only: vector_text
    use mpm_error, only: error_type, fatal_error, exit_numerical
    use mpm_grid, only: grid_type
    use mpm_particles, only: particles_type, particle_number
    use mpm_stencil, only: stencils_type, particle_weights, restencil, chunk_holds, cut_chunks
    use mpm_shape, only: max_stencil_nodes, shape_type
    use mpm_material, only: material_holder_type
    use mpm_kernel_stress, only: stress_block, determinant, gather_block, nstress_sums
    use mpm_kernel_scatter, only: scatter_particle
    use mpm_kernel_gather, only: gather_particle
    use mpm_kernel_nodal, only: box_middle, box_row
    use mpm_kernel_contact, only: contact_gaps
    implicit none
    private
    public :: p2g, p2g_options_type, g2p, motion_type, report_lost, update_stress, nstress_sums
    public :: map_through_particles

    !> What a P2G pass scatters.
    type :: p2g_options_type
        logical :: mass = .false.
            !! mass, momentum and the extra body force
        logical :: fint = .false.
            !! the internal force
        logical :: fbar = .false.
            !! with F-bar, the internal force takes the pressure of each particle as the mean of
            !! its cell, the counterpart of the cell-averaged volume change of `update_stress`
    end type p2g_options_type

    !> What the particles did when they moved in a pass, for the checks of the step.
    type :: motion_type
        real(wp) :: jump = 0.0_wp
            !! largest displacement component of a particle in the step [m]
        integer :: jump_particle = 0
            !! the particle that made it
        real(wp) :: jump_length = 0.0_wp
            !! its displacement length [m]
        integer :: lost = 0
            !! a particle that left the grid (through a free face, or not finite), 0 if none
        real(wp) :: potential = 0.0_wp
            !! change of the gravitational potential energy, - sum m g . dx [J]
        real(wp) :: load_work = 0.0_wp
            !! work of the extra body forces of drivers (particles%body_force) on the moves,
            !! sum m b . dx [J]
    end type motion_type

    !> The P2G of the next step in the last particle pass of a one-pass step (USL, MUSL):
    !> each chunk, after its particles have moved and their stresses are updated, takes its
    !> stencils at the new positions (mpm_stencil::restencil) and scatters mass, momentum and
    !> internal force into its buffer of the step's layout, whose layers and box have room
    !> for the moves (stc%margin). The nodal sums depend only on the order of the particles
    !> and their cut into chunks, not on the layout: a chunk whose stencils do not fit
    !> (a particle that moved more than the margin) is scattered again after the pass with the
    !> layout of the new stencils, to the same bits.
    type :: next_scatter_type
        logical :: on = .false.
            !! the pass scatters the next step's P2G
        integer :: mass_row = 0, fint_row = 0, body_row = 0
            !! rows of the buffers (p2g_rows)
        logical :: apic = .false., body = .false.
            !! APIC momentum, extra body force
        logical, allocatable :: spilled(:)
            !! the chunks whose stencils did not fit (or that lost a particle)
    end type next_scatter_type

contains

    !> Scatter particle mass, momentum and body forces (opts%mass) and the internal force
    !> (opts%fint) to the nodes; the fields not scattered keep their values. With mass, the
    !> smallest gap of each contact pair too.
    !>
    !> f_int,i = - sum_p V_p sigma_p . grad N_i(x_p); in 2D only the in-plane components.
    !> Gravity is not scattered: the nodal update adds m_i g. Only the extra body force of
    !> drivers that prescribe one (particles%body_force) goes to grid%fext. The nodes shared
    !> with other images hold this image's part only (mpm_halo completes them).
    subroutine p2g(grid, particles, stc, opts, box_lo, box_hi)
        type(grid_type), intent(inout), target :: grid
            !! grid receiving the nodal sums
        type(particles_type), intent(in) :: particles
            !! particles
        type(stencils_type), intent(in) :: stc
            !! stencils, order and chunks of the step
        type(p2g_options_type), intent(in) :: opts
            !! what to scatter
        integer, intent(in), optional :: box_lo(3), box_hi(3)
            !! with mass: the box of nodes the step's grid work covers (0-based), when it is
            !! larger than the stencils' (on several images: mpm_halo::halo_box)

        integer :: p, q, k, c, fint_row, body_row, rows, mass_row, lo(3), hi(3)
        logical :: apic, body
        real(wp), allocatable :: cell_pv(:), cell_v(:)
        real(wp), pointer, contiguous :: buf(:, :)

        lo = stc%box_lo
        hi = stc%box_hi
        if (present(box_lo)) lo = box_lo
        if (present(box_hi)) hi = box_hi
        if (opts%fint .and. opts%fbar) then
            ! the stress power sum_p V_p p_p (mean of dJ over the cell) equals
            ! sum_q V_q (mean of V p over the cell) tr(L_q): the force that does the work of
            ! the averaged strains uses the averaged pressure
            allocate (cell_pv(product(grid%ncells)), cell_v(product(grid%ncells)))
            cell_pv = 0.0_wp
            cell_v = 0.0_wp
            do q = 1, particles%n   ! in the sorted order: a fixed order of the sums
                p = stc%order(q)
                c = stc%cell(p)
                cell_pv(c) = cell_pv(c) + particles%volume(p)*sum(particles%stress(1:3, p))/3.0_wp
                cell_v(c) = cell_v(c) + particles%volume(p)
            end do
            where (cell_v > 0.0_wp) cell_pv = cell_pv/cell_v
        else
            allocate (cell_pv(1))
        end if
        call p2g_rows(particles, grid%dim, opts, rows, mass_row, fint_row, body_row, apic, body)
        call scatter_buffer(grid, rows, stc%chunk_offset(stc%nchunks + 1), buf)

        !$omp parallel do default(none) schedule(dynamic, 1) &
        !$omp shared(grid, particles, stc, buf, opts, apic, body, cell_pv, fint_row, body_row, &
        !$omp mass_row) private(k)
        do k = 1, stc%nchunks
            call scatter_chunk(grid, particles, stc, k, opts, apic, body, cell_pv, mass_row, &
                fint_row, body_row, buf)
        end do
        !$omp end parallel do

        call finish_p2g(grid, particles, stc, buf, opts%mass, fint_row, body_row, lo, hi)
    end subroutine p2g

    !> The rows of a P2G pass's buffer (0: a row not scattered), and whether it scatters the
    !> affine velocities (APIC) and the extra body force.
    pure subroutine p2g_rows(particles, dim, opts, rows, mass_row, fint_row, body_row, apic, &
            body)
        type(particles_type), intent(in) :: particles
            !! particles
        integer, intent(in) :: dim
            !! space dimensions
        type(p2g_options_type), intent(in) :: opts
            !! what to scatter
        integer, intent(out) :: rows, mass_row, fint_row, body_row
            !! rows of a node, first rows of the mass (then momentum), internal force and body
            !! force
        logical, intent(out) :: apic, body
            !! APIC momentum, extra body force

        apic = allocated(particles%affine) .and. opts%mass
        body = allocated(particles%body_force) .and. opts%mass
        rows = 0
        mass_row = 0
        if (opts%mass) mass_row = 1
        if (opts%mass) rows = 1 + dim
        fint_row = 0
        if (opts%fint) fint_row = rows + 1
        if (opts%fint) rows = rows + dim
        body_row = 0
        if (body) body_row = rows + 1
        if (body) rows = rows + dim
    end subroutine p2g_rows

    !> P2G of the particles of chunk k into the chunk's part of the buffer (zeroed first), in
    !> their sorted order.
    subroutine scatter_chunk(grid, particles, stc, k, opts, apic, body, cell_pv, mass_row, &
            fint_row, body_row, buf)
        type(grid_type), intent(in) :: grid
            !! the grid (origin and cell size)
        type(particles_type), intent(in) :: particles
            !! particles
        type(stencils_type), intent(in) :: stc
            !! stencils, order and chunks
        integer, intent(in) :: k
            !! the chunk
        type(p2g_options_type), intent(in) :: opts
            !! what to scatter
        logical, intent(in) :: apic, body
            !! APIC momentum, extra body force (p2g_rows)
        real(wp), intent(in) :: cell_pv(:)
            !! with F-bar, the mean pressure of each cell [Pa]
        integer, intent(in) :: mass_row, fint_row, body_row
            !! rows of the buffer (p2g_rows)
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! scatter buffer of the pass

        buf(:, stc%chunk_offset(k) + 1:stc%chunk_offset(k + 1)) = 0.0_wp
        call scatter_range(grid, particles, stc, k, stc%chunk_start(k), &
            stc%chunk_start(k + 1) - 1, opts, apic, body, cell_pv, mass_row, fint_row, &
            body_row, buf)
    end subroutine scatter_chunk

    !> P2G of the particles order(qlo:qhi) of chunk k into the chunk's part of the buffer, in
    !> that order.
    subroutine scatter_range(grid, particles, stc, k, qlo, qhi, opts, apic, body, cell_pv, &
            mass_row, fint_row, body_row, buf)
        type(grid_type), intent(in) :: grid
            !! the grid (origin and cell size)
        type(particles_type), intent(in) :: particles
            !! particles
        type(stencils_type), intent(in) :: stc
            !! stencils, order and chunks
        integer, intent(in) :: k
            !! the chunk
        integer, intent(in) :: qlo, qhi
            !! the particles' range of the order, in the chunk's
        type(p2g_options_type), intent(in) :: opts
            !! what to scatter
        logical, intent(in) :: apic, body
            !! APIC momentum, extra body force (p2g_rows)
        real(wp), intent(in) :: cell_pv(:)
            !! with F-bar, the mean pressure of each cell [Pa]
        integer, intent(in) :: mass_row, fint_row, body_row
            !! rows of the buffer (p2g_rows)
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! scatter buffer of the pass

        integer :: p, q, dim, ns, shift
        real(wp) :: s(6), vs(6), xp(3), vp(3), aff(3, 3), bf(3)

        dim = grid%dim
        ns = particles%nstress
        shift = stc%chunk_base(k)
        xp = 0.0_wp
        vp = 0.0_wp
        aff = 0.0_wp
        bf = 0.0_wp
        s = 0.0_wp
        vs = 0.0_wp
        do q = qlo, qhi
            p = stc%order(q)
            if (opts%mass) then
                vp(1:2) = particles%v(1:2, p)
                if (dim == 3) vp(3) = particles%v(3, p)
                if (apic) then
                    xp(1:dim) = particles%x(:, p)
                    aff(1:dim, 1:dim) = particles%affine(:, :, p)
                end if
                if (body) bf(1:dim) = particles%body_force(:, p)
            end if
            if (opts%fint) then
                ! copies of a size known here (a runtime-sized one calls memcpy)
                if (ns == 4) then
                    s(1:4) = particles%stress(1:4, p)
                else
                    s(1:6) = particles%stress(1:6, p)
                end if
                if (opts%fbar) s(1:3) = s(1:3) + cell_pv(stc%cell(p)) - sum(s(1:3))/3.0_wp
                vs = -particles%volume(p)*s
            end if
            call scatter_particle(stc, grid%origin, grid%dx, p, shift, particles%mass(p), xp, &
                vp, aff, apic, mass_row=mass_row, momentum_row=mass_row + 1, vs=vs, &
                fint_row=fint_row, bf=bf, body_row=body_row, buf=buf)
        end do
    end subroutine scatter_range

    !> The end of a P2G pass: the chunk buffers folded into the grid and, with the masses,
    !> the smallest gap of each contact pair.
    subroutine finish_p2g(grid, particles, stc, buf, with_mass, fint_row, body_row, lo, hi)
        type(grid_type), intent(inout) :: grid
            !! grid receiving the nodal sums
        type(particles_type), intent(in) :: particles
            !! particles
        type(stencils_type), intent(in) :: stc
            !! stencils, order and chunks of the scatter
        real(wp), contiguous, intent(in) :: buf(:, :)
            !! the chunk buffers
        logical, intent(in) :: with_mass
            !! the buffers hold masses and momenta (rows 1 : 1 + dim)
        integer, intent(in) :: fint_row, body_row
            !! first rows of the internal and the extra body force, 0 for none
        integer, intent(in) :: lo(3), hi(3)
            !! with mass, the box of nodes of the step's grid work

        integer :: p
        real(wp), allocatable :: gaps(:)

        call fold(grid, stc, buf, mass_rows=with_mass, fint_row=fint_row, body_row=body_row, &
            box_lo=lo, box_hi=hi)
        if (with_mass .and. grid%ncontacts > 0) then
            ! the smallest gap per pair: a minimum, the same whatever the order (threads)
            allocate (gaps(grid%ncontacts))
            gaps = huge(1.0_wp)
            !$omp parallel do default(none) schedule(static) shared(grid, particles, stc) &
            !$omp private(p) reduction(min: gaps)
            do p = 1, particles%n
                call contact_gaps(grid, particles, stc, p, gaps)
            end do
            !$omp end parallel do
            grid%contact_gap = gaps
        end if
    end subroutine finish_p2g

    !> The options of the next step's P2G of a one-pass step: mass, momentum and internal
    !> force.
    pure function next_options() result(opts)
        type(p2g_options_type) :: opts
        opts = p2g_options_type(mass=.true., fint=.true.)
    end function next_options

    !> Start the next step's P2G in a pass: the rows and the chunk buffers.
    subroutine open_next_scatter(grid, particles, stc, next, buf)
        type(grid_type), intent(inout), target :: grid
            !! grid owning the buffers
        type(particles_type), intent(in) :: particles
            !! particles
        type(stencils_type), intent(in) :: stc
            !! stencils, order and chunks of the step (its layout with stc%margin)
        type(next_scatter_type), intent(inout) :: next
            !! the scatter
        real(wp), pointer, contiguous, intent(out) :: buf(:, :)
            !! the chunk buffers

        integer :: rows

        call p2g_rows(particles, grid%dim, next_options(), rows, next%mass_row, next%fint_row, &
            next%body_row, next%apic, next%body)
        call scatter_buffer(grid, rows, stc%chunk_offset(stc%nchunks + 1), buf)
        allocate (next%spilled(stc%nchunks))
        next%spilled = .false.
    end subroutine open_next_scatter

    !> The next step's P2G of the particles order(qlo:qhi) of chunk k (a block of it, the
    !> blocks in order; the chunk's buffer zeroed before the first), after their moves and
    !> stress updates, while they are in the cache: their stencils at the new positions, and
    !> their scatter when they fit the chunk's layout (not when the chunk lost a particle:
    !> the step fails).
    subroutine next_scatter(grid, particles, stc, shape, k, qlo, qhi, lost, next, buf)
        type(grid_type), intent(in) :: grid
            !! the grid
        type(particles_type), intent(in) :: particles
            !! particles, moved
        type(stencils_type), intent(inout) :: stc
            !! stencils (those of the chunk's particles replaced), order and chunks
        class(shape_type), intent(in) :: shape
            !! shape function
        integer, intent(in) :: k
            !! the chunk
        integer, intent(in) :: qlo, qhi
            !! the block's range of the order
        logical, intent(in) :: lost
            !! a particle of the chunk left the grid
        type(next_scatter_type), intent(inout) :: next
            !! the scatter
        real(wp), contiguous, intent(inout) :: buf(:, :)
            !! the chunk buffers

        real(wp) :: no_cells(1)

        if (qlo == stc%chunk_start(k)) buf(:, stc%chunk_offset(k) + 1:stc%chunk_offset(k + 1)) &
            = 0.0_wp
        next%spilled(k) = next%spilled(k) .or. lost
        if (next%spilled(k)) return
        call restencil(stc, grid, particles, shape, stc%order(qlo:qhi))
        next%spilled(k) = .not. chunk_holds(stc, k, qlo, qhi)
        no_cells = 0.0_wp
        if (.not. next%spilled(k)) call scatter_range(grid, particles, stc, k, qlo, qhi, &
            next_options(), next%apic, next%body, no_cells, next%mass_row, next%fint_row, &
            next%body_row, buf)
    end subroutine next_scatter

    !> End the next step's P2G of a pass: fold the chunk buffers into the grid, or, when some
    !> chunk's stencils did not fit, scatter every chunk again with the layout of the new
    !> stencils (the same order and chunks: the same sums). Nothing when a particle was lost.
    subroutine close_next_scatter(grid, particles, stc, next, buf, lost)
        type(grid_type), intent(inout), target :: grid
            !! grid receiving the next step's nodal sums
        type(particles_type), intent(in) :: particles
            !! particles, moved
        type(stencils_type), intent(inout) :: stc
            !! stencils at the new positions (their layout cut again after a spill)
        type(next_scatter_type), intent(in) :: next
            !! the scatter
        real(wp), contiguous, intent(in) :: buf(:, :)
            !! the chunk buffers
        logical, intent(in) :: lost
            !! a particle left the grid in the pass

        if (lost) return
        if (any(next%spilled)) then
            call cut_chunks(stc, grid)
            call p2g(grid, particles, stc, next_options())
        else
            call finish_p2g(grid, particles, stc, buf, .true., next%fint_row, next%body_row, &
                stc%box_lo, stc%box_hi)
        end if
    end subroutine close_next_scatter

    !> A rows x n view of the grid's scatter scratch, which grows when it is too small and is
    !> kept from pass to pass.
    subroutine scatter_buffer(grid, rows, n, buf)
        type(grid_type), intent(inout), target :: grid
            !! grid owning the scratch
        integer, intent(in) :: rows, n
            !! shape of the buffer
        real(wp), pointer, contiguous, intent(out) :: buf(:, :)
            !! the buffer (contents undefined)

        if (allocated(grid%scratch)) then
            if (size(grid%scratch) < rows*n) deallocate (grid%scratch)
        end if
        if (.not. allocated(grid%scratch)) allocate (grid%scratch(max(1, rows*n)))
        buf(1:rows, 1:n) => grid%scratch(1:rows*n)
    end subroutine scatter_buffer

    !> Nodal sums from the chunk buffers, added chunk by chunk in a fixed order, for the nodes
    !> of the step's box (nodes no chunk touches get zero): mass and momentum (rows
    !> 1 : 1 + dim) when `mass_rows`, the internal force from fint_row, the extra body force
    !> from body_row.
    subroutine fold(grid, stc, buf, mass_rows, fint_row, body_row, only_momentum, box_lo, &
            box_hi)
        type(grid_type), intent(inout) :: grid
        type(stencils_type), intent(in) :: stc
        real(wp), contiguous, intent(in) :: buf(:, :)
        logical, intent(in) :: mass_rows
        integer, intent(in) :: fint_row, body_row
        logical, intent(in), optional :: only_momentum
            !! set the momentum only, from rows 1 : dim (the MUSL remap)
        integer, intent(in), optional :: box_lo(3), box_hi(3)
            !! with mass rows (not only_momentum): the box of nodes of the step's grid work

        integer :: layer, id, k, b, rows, dim, lo(3), hi(3), j, x, y, z, first, last
        real(wp) :: total(10)
        logical :: momentum, row_inside, inside

        momentum = .false.
        if (present(only_momentum)) momentum = only_momentum
        rows = size(buf, 1)
        dim = grid%dim
        if (mass_rows .and. .not. momentum) then
            ! grid work only where the material is: this pass writes the box of nodes it
            ! touches and zeroes every field of the nodes of the last box that it does not
            ! touch; the nodal loops then cover its box (on several images, also the shared
            ! nodes the neighbours' particles touch: halo_box)
            lo = max(0, min(box_lo, grid%active_lo))
            hi = min(grid%nn - 1, max(box_hi, grid%active_hi))
            grid%active_lo = box_lo
            grid%active_hi = box_hi
        else
            lo = grid%active_lo
            hi = grid%active_hi
        end if
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(grid, stc, buf, mass_rows, fint_row, body_row, rows, dim, momentum, lo, hi) &
        !$omp private(layer, j, id, k, b, total, x, y, z, first, last, row_inside, inside)
        do layer = lo(dim), hi(dim)
            do j = box_middle(lo, dim), box_middle(hi, dim)
                call box_row(grid, lo, hi, layer, j, first, last, y, z)
                row_inside = stc%layer_chunks(1, layer) <= stc%layer_chunks(2, layer)
                if (dim == 3) row_inside = row_inside .and. y >= stc%box_lo(2) &
                    .and. y <= stc%box_hi(2)
                do id = first, last
                    x = lo(1) + (id - first)
                    inside = row_inside .and. x >= stc%box_lo(1) .and. x <= stc%box_hi(1)
                    total(1:rows) = 0.0_wp
                    if (inside) then
                        do k = stc%layer_chunks(1, layer), stc%layer_chunks(2, layer)
                            b = stc%chunk_base(k) + 1 + x + stc%bstride(2)*y + stc%bstride(3)*z
                            total(1:rows) = total(1:rows) + buf(:, b)
                        end do
                    end if
                    if (momentum) then
                        grid%momentum(:, id) = total(1:dim)
                    else if (mass_rows) then
                        grid%mass(id) = total(1)
                        grid%momentum(:, id) = total(2:1 + dim)
                        if (.not. inside) then
                            grid%velocity(:, id) = 0.0_wp
                            grid%acceleration(:, id) = 0.0_wp
                        end if
                        if (body_row > 0) then
                            grid%fext(:, id) = total(body_row:body_row + dim - 1)
                        else
                            grid%fext(:, id) = 0.0_wp
                        end if
                    end if
                    if (fint_row > 0) grid%fint(:, id) = total(fint_row:fint_row + dim - 1)
                end do
            end do
        end do
        !$omp end parallel do
    end subroutine fold

    !> One pass of a nodal field through the particles, for XPIC: the momentum
    !> grid%momentum_i = sum_p m_p N_ip (sum_j N_jp u_j) of this image's particles (the
    !> images' parts of the shared nodes still to be added, mpm_halo::halo_sum), for the nodes
    !> of the step's box, in the fixed order of the chunk buffers.
    subroutine map_through_particles(grid, particles, stc, u)
        type(grid_type), intent(inout), target :: grid
            !! grid of the step (its momentum is replaced)
        type(particles_type), intent(in) :: particles
            !! particles
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        real(wp), intent(in), contiguous :: u(:, :)
            !! nodal field (dim, nnodes)

        integer :: k, q, p, dim, shift, qlo, qhi
        real(wp) :: w(3), unused(3), none(3, 3), xp(3), aff(3, 3), bf(3), vs(6)
        real(wp), pointer, contiguous :: buf(:, :)

        dim = grid%dim
        call scatter_buffer(grid, dim, stc%chunk_offset(stc%nchunks + 1), buf)
        !$omp parallel do default(none) schedule(dynamic, 1) &
        !$omp shared(grid, particles, stc, u, buf, dim) &
        !$omp private(k, q, p, shift, w, unused, none, qlo, qhi, xp, aff, bf, vs)
        do k = 1, stc%nchunks
            call group_range(stc, .true., k, qlo, qhi)
            shift = stc%chunk_base(k)
            buf(:, stc%chunk_offset(k) + 1:stc%chunk_offset(k + 1)) = 0.0_wp
            xp = 0.0_wp
            aff = 0.0_wp
            bf = 0.0_wp
            vs = 0.0_wp
            w = 0.0_wp
            do q = qlo, qhi
                p = stc%order(q)
                call gather_particle(stc, p, u, u, with_a=.true., with_v=.false., &
                    with_gradient=.false., a=w, v=unused, gradient=none)
                call scatter_particle(stc, grid%origin, grid%dx, p, shift, particles%mass(p), &
                    xp, w, aff, .false., mass_row=0, momentum_row=1, vs=vs, fint_row=0, bf=bf, &
                    body_row=0, buf=buf)
            end do
        end do
        !$omp end parallel do
        call fold(grid, stc, buf, mass_rows=.true., fint_row=0, body_row=0, &
            only_momentum=.true.)
    end subroutine map_through_particles

    !> Gather nodal accelerations and velocities: v_p += dt sum N_i a_i (FLIP), and, unless
    !> `remap`, move the particle by dx_p = dt sum N_i v_i (the later passes of the step use
    !> the stencils of the start-of-step positions, not the positions).
    !>
    !> With `remap` (MUSL), the same pass maps the updated particle momentum back to the nodes
    !> (chunk buffers folded in a fixed order, as in p2g); the step then completes the shared
    !> nodes (mpm_halo) and recomputes the nodal velocities (nodal_velocity).
    !> With `materials` (USL without F-bar, whose stress update uses the same nodal velocities
    !> as the moves), the same pass also updates the stresses: one gather per particle and step
    !> instead of two; the blocks and the order of the work sums are those of update_stress.
    subroutine g2p(grid, particles, stc, dt, flip, gravity, remap, motion, kinetic, materials, &
            strain_work, blend_loss, xpic, shape)
        type(grid_type), intent(inout), target :: grid
            !! grid after the nodal update (momentum replaced with `remap`; with `shape`, the
            !! P2G of the next step)
        type(particles_type), intent(inout) :: particles
            !! particles whose velocities are updated
        type(stencils_type), intent(inout) :: stc
            !! stencils, order and chunks of the step (with `shape`, the stencils at the
            !! particles' new positions on return)
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: flip
            !! FLIP fraction of the velocity update (1: FLIP, 0: PIC) [-]
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration (potential energy of the moves) [m/s2]
        logical, intent(in) :: remap
            !! for MUSL, scatter the updated momentum and recompute the nodal velocities; the
            !! particles then move in the stress update, with the remapped velocities
        type(motion_type), intent(out) :: motion
            !! largest move and lost particle when the particles move here (not remap)
        real(wp), intent(out) :: kinetic
            !! kinetic energy of the particles with their new velocities, sum_p m |v|^2 / 2 [J]
            !! (per metre in 2D)
        type(material_holder_type), intent(in), optional :: materials(:)
            !! materials of the case: update the stresses in this pass (not with remap)
        real(wp), intent(out), optional :: strain_work(nstress_sums)
            !! with materials: sum_p (V sigma)_mid : d_eps and the stored elastic energy, by
            !! work kind (nstress_sums) [J] (per metre in 2D)
        real(wp), intent(out), optional :: blend_loss
            !! a FLIP-PIC blend (0 < flip < 1): the kinetic energy its PIC part takes from the
            !! FLIP velocities, sum_p m (|v_FLIP|^2 - |v|^2) / 2 [J] (per metre in 2D); with
            !! `xpic` the velocity its filter removes at the mean velocity of the step,
            !! sum_p m (v_p - v_x) . (v_p + v_new) / 2; 0 otherwise
        logical, intent(in), optional :: xpic
            !! XPIC(m) update (solver.transfer = "xpic"): v_p = sum N_i (grid%xpic_i + dt a_i),
            !! with grid%xpic set by the XPIC pass of the step (default .false.)
        class(shape_type), intent(in), optional :: shape
            !! with materials, a one-pass step: after the moves and the stresses of a chunk,
            !! its stencils at the new positions and its P2G of the next step (next_scatter)

        integer :: k, q, p, dim, shift, ng, qlo, qhi, q0, q1
        real(wp) :: xp(3), vp(3), aff(3, 3), bf(3), vs(6), dx(3), gradv(3, 3), ke, loss, &
            blended, ldts(3, 3, gather_block), work(nstress_sums)
        logical :: apic, stress, extended, chunks
        real(wp), allocatable :: partial(:, :), partial_ke(:), partial_loss(:)
        real(wp), pointer, contiguous :: buf(:, :)
        type(motion_type), allocatable :: moved(:)
        type(motion_type) :: mine
        type(next_scatter_type) :: next

        dim = grid%dim
        apic = allocated(particles%affine)
        extended = .false.
        if (present(xpic)) extended = xpic
        stress = present(materials) .and. .not. remap
        next%on = present(shape) .and. stress
        ! the scatters (remap, next step) by chunks; otherwise only gathers: small blocks
        ! balance the threads
        chunks = remap .or. next%on
        ng = group_count(stc, chunks)
        allocate (moved(ng), partial(nstress_sums, ng), partial_ke(ng), partial_loss(ng))
        if (remap) then
            ! the momentum only: the nodal masses do not change
            call scatter_buffer(grid, dim, stc%chunk_offset(stc%nchunks + 1), buf)
        else if (next%on) then
            call open_next_scatter(grid, particles, stc, next, buf)
        else
            call scatter_buffer(grid, 1, 1, buf)
        end if
        !$omp parallel do default(none) schedule(dynamic, 1) &
        !$omp shared(grid, particles, stc, dt, flip, gravity, remap, buf, dim, apic, moved, ng, &
        !$omp materials, stress, partial, partial_ke, partial_loss, extended, chunks, next, shape) &
        !$omp private(k, q, p, shift, xp, vp, aff, bf, vs, dx, qlo, qhi, mine, gradv, work, ldts, &
        !$omp ke, loss, blended, q0, q1)
        do k = 1, ng
            ! records and sums in private variables, stored once per group: neighbouring
            ! groups run on other threads, and their array entries share cache lines
            mine = motion_type()
            work = 0.0_wp
            ke = 0.0_wp
            loss = 0.0_wp
            call group_range(stc, chunks, k, qlo, qhi)
            shift = 0
            if (remap) then
                shift = stc%chunk_base(k)
                buf(:, stc%chunk_offset(k) + 1:stc%chunk_offset(k + 1)) = 0.0_wp
            end if
            xp = 0.0_wp
            vp = 0.0_wp
            aff = 0.0_wp
            bf = 0.0_wp
            vs = 0.0_wp
            ! the stresses by blocks of at most gather_block particles (a chunk holds several)
            do q0 = qlo, qhi, gather_block
                q1 = min(q0 + gather_block - 1, qhi)
                do q = q0, q1
                    p = stc%order(q)
                    call update_particle_velocity(grid, particles, stc, p, dt, flip, apic, &
                        need_v=.not. remap, with_gradient=stress, dx=dx, gradv=gradv, &
                        blend_loss=blended, xpic=extended)
                    ke = ke + 0.5_wp*particles%mass(p)*sum(particles%v(:, p)**2)
                    loss = loss + blended
                    if (.not. remap) call move_particle(grid, particles, p, dx, gravity, mine)
                    if (stress) ldts(:, :, q - q0 + 1) = dt*gradv
                    if (remap) then
                        vp(1:dim) = particles%v(:, p)
                        if (apic) then
                            xp(1:dim) = particles%x(:, p)
                            aff(1:dim, 1:dim) = particles%affine(:, :, p)
                        end if
                        call scatter_particle(stc, grid%origin, grid%dx, p, shift, &
                            particles%mass(p), xp, vp, aff, apic, mass_row=0, momentum_row=1, &
                            vs=vs, fint_row=0, bf=bf, body_row=0, buf=buf)
                    end if
                end do
                if (stress) call stress_block(stc%order(q0:q1), particles%material, &
                    particles%stress, particles%state, particles%f, particles%volume, &
                    particles%volume0, materials, ldts, dt, dim, work, strain=particles%strain)
                if (next%on) call next_scatter(grid, particles, stc, shape, k, q0, q1, &
                    mine%lost > 0, next, buf)
            end do
            moved(k) = mine
            partial(:, k) = work
            partial_ke(k) = ke
            partial_loss(k) = loss
        end do
        !$omp end parallel do
        call merge_motion(moved, motion)
        kinetic = 0.0_wp
        do k = 1, ng
            kinetic = kinetic + partial_ke(k)
        end do
        if (present(blend_loss)) then
            blend_loss = 0.0_wp
            do k = 1, ng
                blend_loss = blend_loss + partial_loss(k)
            end do
        end if
        if (present(strain_work)) then
            strain_work = 0.0_wp
            do k = 1, ng
                strain_work = strain_work + partial(:, k)
            end do
        end if
        if (remap) then
            call fold(grid, stc, buf, mass_rows=.true., fint_row=0, body_row=0, &
                only_momentum=.true.)
        end if
        if (next%on) call close_next_scatter(grid, particles, stc, next, buf, motion%lost > 0)
    end subroutine g2p

    !> The G2P update of one particle: velocity (FLIP, PIC blend or APIC) and the position
    !> increment dt sum N_i v_i; the velocity gradient too with `with_gradient` (or APIC).
    subroutine update_particle_velocity(grid, particles, stc, p, dt, flip, apic, need_v, &
            with_gradient, dx, gradv, blend_loss, xpic)
        type(grid_type), intent(in) :: grid
        type(particles_type), intent(inout) :: particles
        type(stencils_type), intent(in) :: stc
        integer, intent(in) :: p
        real(wp), intent(in) :: dt, flip
        logical, intent(in) :: apic, with_gradient
        logical, intent(in) :: need_v
            !! the increment dx is used (the particle moves in this pass)
        real(wp), intent(out) :: dx(3), gradv(3, 3)
        real(wp), intent(out) :: blend_loss
            !! a FLIP-PIC blend: m (|v_FLIP|^2 - |v|^2) / 2, the kinetic energy the PIC part
            !! takes from the FLIP update (it can give some to a particle); with `xpic`
            !! m (v_p - v_x) . (v_p + v_new) / 2, the velocity the filter removes at the mean
            !! velocity of the step (as damping is booked); 0 otherwise [J]
        logical, intent(in) :: xpic
            !! XPIC(m): v_p = sum N_i (grid%xpic_i + dt a_i)

        integer :: dim
        real(wp) :: a(3), v(3), kept, vflip(3), start(3), unused(3), none(3, 3)

        dim = grid%dim
        blend_loss = 0.0_wp
        ! the MUSL remap (FLIP) needs the accelerations only: the particles move later
        call gather_particle(stc, p, grid%acceleration, grid%velocity, with_a=.not. apic, &
            with_v=need_v .or. apic .or. flip < 1.0_wp, with_gradient=apic .or. with_gradient, &
            a=a, v=v, gradient=gradv)
        if (apic) then
            ! APIC: the particle takes the nodal velocity field, its value and its gradient.
            ! A particle alone on its nodes would only get back the affine field it gave
            ! them, and a stretching one would keep stretching without end (its volume grew
            ! by 1e72 at the front of a collapse); alone, it moves without an affine part.
            ! Alone on some of them is enough: where the others' nodes are at rest, its own
            ! nodes give its affine field back with a gain of one, so a stretch kicked into a
            ! stress-free (separated) particle lying on a deposit grew exponentially (42 V0 in
            ! 0.05 s, a = 2, 6.25 mm cells). It keeps the affine part in proportion to its
            ! weight on the nodes it does not hold (more than half of their mass): all of it
            ! inside the material, none when alone.
            particles%v(:, p) = v(1:dim)
            kept = unheld_weight(grid, stc, p, particles%mass(p))
            if (kept >= 1.0_wp) then
                particles%affine(:, :, p) = gradv(1:dim, 1:dim)
            else if (kept > 0.0_wp) then
                particles%affine(:, :, p) = kept*gradv(1:dim, 1:dim)
            else
                particles%affine(:, :, p) = 0.0_wp
            end if
        else if (xpic) then
            ! XPIC(m) (Hammerquist and Nairn 2017): the FLIP increment on the particle's start
            ! velocity with its null-space part taken out, sum N_i xpic_i (mpm_step_passes::
            ! xpic_field)
            call gather_particle(stc, p, grid%xpic, grid%xpic, with_a=.true., with_v=.false., &
                with_gradient=.false., a=start, v=unused, gradient=none)
            vflip(1:dim) = particles%v(:, p)
            particles%v(:, p) = start(1:dim) + dt*a(1:dim)
            ! the velocity the filter removes, v_p - sum N_i xpic_i, times the mean velocity
            ! of the step, (v_p + v_new) / 2, as the nodal update books damping
            blend_loss = 0.5_wp*particles%mass(p)*dot_product(vflip(1:dim) - start(1:dim), &
                vflip(1:dim) + particles%v(:, p))
        else if (flip < 1.0_wp) then
            ! the velocity as FLIP alone would give it, for the loss only (the blend keeps its
            ! own expression: the moves are those of the runs before the loss was booked)
            vflip(1:dim) = particles%v(:, p) + dt*a(1:dim)
            particles%v(:, p) = flip*(particles%v(:, p) + dt*a(1:dim)) + (1.0_wp - flip)*v(1:dim)
            blend_loss = 0.5_wp*particles%mass(p)* &
                (sum(vflip(1:dim)**2) - sum(particles%v(:, p)**2))
        else
            particles%v(:, p) = particles%v(:, p) + dt*a(1:dim)
        end if
        dx = dt*v
    end subroutine update_particle_velocity

    !> Move particle p by dx and record the move in `motion` (largest move, lost particle).
    !>
    !> A closed face (sliding, fixed, frictional) cannot be crossed: the nodal velocity keeps
    !> material off it, but a point carried by the velocities of the nodes beside the face can
    !> overshoot it by a fraction of a step; it stays on the face. A particle beyond a free
    !> face, or with a position that is not finite, is lost.
    pure subroutine move_particle(grid, particles, p, dx, gravity, motion)
        type(grid_type), intent(in) :: grid
            !! grid (extent and faces)
        type(particles_type), intent(inout) :: particles
            !! particles
        integer, intent(in) :: p
            !! particle
        real(wp), intent(in) :: dx(3)
            !! position increment (first dim components) [m]
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        type(motion_type), intent(inout) :: motion
            !! record of the moves of a chunk

        ! one variant per dimension: the maxima, clamps and copies over the axes have a
        ! length known to the compiler (no memcpy call per particle); the energy sums keep
        ! their loops of runtime length (mpm_transfer_move.inc)
        if (grid%dim == 2) then
            call move_particle_2d(grid, particles, p, dx, gravity, motion)
        else
            call move_particle_3d(grid, particles, p, dx, gravity, motion)
        end if
    end subroutine move_particle

    !> move_particle in 2D.
    pure subroutine move_particle_2d(grid, particles, p, dx, gravity, motion)
        integer, parameter :: dim = 2
        include "mpm_transfer_move.inc"
    end subroutine move_particle_2d

    !> move_particle in 3D.
    pure subroutine move_particle_3d(grid, particles, p, dx, gravity, motion)
        integer, parameter :: dim = 3
        include "mpm_transfer_move.inc"
    end subroutine move_particle_3d

    !> The record of a pass from those of its chunks, in chunk order (the same with any number
    !> of threads).
    pure subroutine merge_motion(moved, motion)
        type(motion_type), intent(in) :: moved(:)
        type(motion_type), intent(out) :: motion

        integer :: k

        do k = 1, size(moved)
            if (moved(k)%jump > motion%jump) then
                motion%jump = moved(k)%jump
                motion%jump_particle = moved(k)%jump_particle
                motion%jump_length = moved(k)%jump_length
            end if
            if (motion%lost == 0) motion%lost = moved(k)%lost
            motion%potential = motion%potential + moved(k)%potential
            motion%load_work = motion%load_work + moved(k)%load_work
        end do
    end subroutine merge_motion

    !> The error of a particle that left the grid (`lo`, `hi`: the corners of the whole grid).
    subroutine report_lost(lo, hi, particles, p, error)
        real(wp), intent(in) :: lo(3), hi(3)
        type(particles_type), intent(in) :: particles
        integer, intent(in) :: p
        type(error_type), allocatable, intent(out) :: error

        character(len=600) :: msg
        integer :: dim

        dim = particles%dim
        write (msg, "(a,i0,a,a,a,a,a,a,a)") "particle ", particle_number(particles, p), &
            " left the grid: position (", &
            vector_text(particles%x(:, p)), ") m, grid from (", vector_text(lo(1:dim)), &
            ") to (", vector_text(hi(1:dim)), &
            ") m; enlarge the domain or close its faces with boundary conditions"
        call fatal_error(error, trim(msg), exit_numerical)
    end subroutine report_lost

    !> Stress update from the nodal velocities in grid%velocity.
    !>
    !> L = sum_i v_i (x) grad N_i; strain increment D dt, spin W dt; F <- (I + L dt) F;
    !> V = det(F) V0 (the GIMP half-sizes follow from F: domain_half_sizes). Returns the
    !> work of the stresses over the step (strain energy increment). Like every pass of a
    !> step, it uses the shape functions at the start-of-step positions.
    !>
    !> With `fbar`, the volumetric part of each increment is replaced by the mean of the cell
    !> the particle is in (F-bar: dF_bar = (dJ_cell / dJ_p)^(1/dim) dF_p, with dJ_cell the
    !> volume-weighted mean of dJ over the particles of the cell). Nearly isochoric plastic
    !> flow (Mohr-Coulomb with psi = 0) otherwise locks on the low-order shape functions and
    !> leaves a checkerboard of pressures, and with it of strengths, between the particles of
    !> a cell (Coombs et al. 2018; Wyser et al. 2021 average the pressure per cell).
    subroutine update_stress(grid, particles, stc, materials, dt, fbar, strain_work, gravity, &
            motion, shape)
        type(grid_type), intent(inout), target :: grid
            !! grid with nodal velocities (with `shape`, the P2G of the next step on return)
        type(particles_type), intent(inout) :: particles
            !! particles to update
        type(stencils_type), intent(inout) :: stc
            !! stencils, order and chunks of the step (with `shape`, the stencils at the
            !! particles' new positions on return)
        type(material_holder_type), intent(in) :: materials(:)
            !! materials of the case
        real(wp), intent(in) :: dt
            !! time step [s]
        logical, intent(in) :: fbar
            !! average the volume change of the step per cell
        real(wp), intent(out) :: strain_work(nstress_sums)
            !! sum_p (V sigma)_mid : d_eps and the stored elastic energy at the end of the
            !! step, by work kind (nstress_sums) [J] (per metre in 2D)
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration (potential energy of the moves) [m/s2]
        type(motion_type), intent(out), optional :: motion
            !! when present (MUSL), the particles move by dt sum_i N_i v_i with the same nodal
            !! velocities as the strain, and this records the moves
        class(shape_type), intent(in), optional :: shape
            !! with motion and without fbar, a one-pass step: after the moves and the stresses
            !! of a chunk, its stencils at the new positions and its P2G of the next step
            !! (next_scatter)

        integer :: p, q, k, dim, a
        real(wp) :: gradv(3, 3), ldt(3, 3), dF(3, 3), jac, scale, v(3), a3(3), &
            ldts(3, 3, gather_block)
        integer :: ng, qlo, qhi, q0, q1
        real(wp), allocatable :: grads(:, :, :), vels(:, :), cell_old(:), cell_new(:), &
            partial(:, :)
        real(wp), pointer, contiguous :: buf(:, :)
        type(motion_type), allocatable :: moved(:)
        type(motion_type) :: mine
        type(next_scatter_type) :: next
        real(wp) :: work(nstress_sums)
        logical :: move

        dim = grid%dim
        move = present(motion)
        next%on = present(shape) .and. move .and. .not. fbar
        if (fbar) then
            allocate (grads(3, 3, particles%n), vels(3, particles%n))
            allocate (cell_old(product(grid%ncells)), cell_new(product(grid%ncells)))
            !$omp parallel do default(none) schedule(static) &
            !$omp shared(grid, particles, stc, grads, vels) private(p, a3)
            do p = 1, particles%n
                call gather_particle(stc, p, grid%velocity, grid%velocity, with_a=.false., &
                    with_v=.true., with_gradient=.true., a=a3, v=vels(:, p), &
                    gradient=grads(:, :, p))
            end do
            !$omp end parallel do
            cell_old = 0.0_wp
            cell_new = 0.0_wp
            do q = 1, particles%n   ! serial, in the sorted order: a fixed order of the sums
                p = stc%order(q)
                dF = increment(grads(:, :, p), dt, dim)
                cell_old(stc%cell(p)) = cell_old(stc%cell(p)) + particles%volume(p)
                cell_new(stc%cell(p)) = cell_new(stc%cell(p)) &
                    + particles%volume(p)*determinant(dF, dim)
            end do
        end if
        ! by chunks when the pass scatters the next step's P2G; otherwise small blocks
        ! balance the threads
        ng = group_count(stc, chunks=next%on)
        allocate (partial(nstress_sums, ng), moved(ng))
        if (next%on) then
            call open_next_scatter(grid, particles, stc, next, buf)
        else
            call scatter_buffer(grid, 1, 1, buf)
        end if
        !$omp parallel do default(none) schedule(dynamic, 1) &
        !$omp shared(grid, particles, stc, materials, dt, dim, fbar, grads, vels, gravity, &
        !$omp cell_old, cell_new, move, moved, partial, ng, next, shape, buf) &
        !$omp private(k, q, p, gradv, v, ldt, dF, jac, a, scale, a3, qlo, qhi, work, mine, ldts, &
        !$omp q0, q1)
        do k = 1, ng
            work = 0.0_wp
            mine = motion_type()
            call group_range(stc, chunks=next%on, g=k, qlo=qlo, qhi=qhi)
            ! by blocks of at most gather_block particles (a chunk holds several)
            do q0 = qlo, qhi, gather_block
                q1 = min(q0 + gather_block - 1, qhi)
                do q = q0, q1
                    p = stc%order(q)
                    if (fbar) then
                        gradv = grads(:, :, p)
                        v = vels(:, p)
                    else
                        call gather_particle(stc, p, grid%velocity, grid%velocity, with_a=.false., &
                            with_v=.true., with_gradient=.true., a=a3, v=v, gradient=gradv)
                    end if
                    ! gradv(i, j) = d v_i / d x_j; ldt = dt gradv, dF = I + ldt
                    ldt = dt*gradv
                    if (fbar) then
                        dF = increment(gradv, dt, dim)
                        jac = determinant(dF, dim)
                        if (jac > 0.0_wp .and. cell_new(stc%cell(p)) > 0.0_wp) then
                            scale = (cell_new(stc%cell(p))/(cell_old(stc%cell(p))*jac)) &
                                **(1.0_wp/dim)
                            ldt(1:dim, 1:dim) = scale*dF(1:dim, 1:dim)
                            do a = 1, dim
                                ldt(a, a) = ldt(a, a) - 1.0_wp
                            end do
                        end if
                    end if
                    ldts(:, :, q - q0 + 1) = ldt
                    if (move) call move_particle(grid, particles, p, dt*v, gravity, mine)
                end do
                call stress_block(stc%order(q0:q1), particles%material, particles%stress, &
                    particles%state, particles%f, particles%volume, particles%volume0, &
                    materials, ldts, dt, dim, work, strain=particles%strain)
                if (next%on) call next_scatter(grid, particles, stc, shape, k, q0, q1, &
                    mine%lost > 0, next, buf)
            end do
            ! stored once per group (neighbouring entries share cache lines across threads)
            partial(:, k) = work
            moved(k) = mine
        end do
        !$omp end parallel do
        if (move) call merge_motion(moved, motion)
        strain_work = 0.0_wp
        do k = 1, ng
            strain_work = strain_work + partial(:, k)
        end do
        if (next%on) call close_next_scatter(grid, particles, stc, next, buf, motion%lost > 0)
    end subroutine update_stress

    !> Groups of sorted particles of a pass: the scatter chunks (`chunks`), or blocks of
    !> gather_block particles for passes that only gather.
    pure integer function group_count(stc, chunks)
        type(stencils_type), intent(in) :: stc
        logical, intent(in) :: chunks
        if (chunks) then
            group_count = stc%nchunks
        else
            group_count = (stc%n + gather_block - 1)/gather_block
        end if
    end function group_count

    !> Range qlo:qhi of stc%order that group g holds (see group_count).
    pure subroutine group_range(stc, chunks, g, qlo, qhi)
        type(stencils_type), intent(in) :: stc
        logical, intent(in) :: chunks
        integer, intent(in) :: g
        integer, intent(out) :: qlo, qhi
        if (chunks) then
            qlo = stc%chunk_start(g)
            qhi = stc%chunk_start(g + 1) - 1
        else
            qlo = (g - 1)*gather_block + 1
            qhi = min(g*gather_block, stc%n)
        end if
    end subroutine group_range

    !> The weight of particle p of mass m on the nodes of its stencil that it does not hold
    !> (it holds a node with more than half of its mass); exactly 1 when it holds none, 0 when
    !> it is alone on its nodes.
    pure real(wp) function unheld_weight(grid, stc, p, m)
        type(grid_type), intent(in) :: grid
            !! grid with nodal masses
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: p
            !! particle
        real(wp), intent(in) :: m
            !! particle mass [kg]
        integer :: i, j, k, nk, base, basej
        real(wp) :: wk, wjk, w
        logical :: held
        ! the nodes in the order of particle_nodes, each weight the same product (bit for
        ! bit: in 2D wk = 1 exactly), tested where it is formed: no stencil arrays (every
        ! particle, every step)
        held = .false.
        unheld_weight = 0.0_wp
        if (.not. stc%tensor) then
            unheld_weight = unheld_weight_full(grid, stc, p, m)
            return
        end if
        nk = 1
        if (stc%dim == 3) nk = stc%nper(3)
        do k = 1, nk
            wk = 1.0_wp
            base = 1 + stc%first(1, p) + stc%stride(2)*stc%first(2, p)
            if (stc%dim == 3) then
                wk = stc%w(k, 3, p)
                base = base + stc%stride(3)*(stc%first(3, p) + k - 1)
            end if
            do j = 1, stc%nper(2)
                wjk = stc%w(j, 2, p)*wk
                basej = base + stc%stride(2)*(j - 1) - 1
                do i = 1, stc%nper(1)
                    w = stc%w(i, 1, p)*wjk
                    if (w <= 0.0_wp) cycle
                    if (m*w > 0.5_wp*grid%mass(basej + i)) then
                        held = .true.
                    else
                        unheld_weight = unheld_weight + w
                    end if
                end do
            end do
        end do
        if (.not. held) unheld_weight = 1.0_wp
    end function unheld_weight

    !> unheld_weight for a stencil that is no tensor product (CPDI), from its node weights.
    pure real(wp) function unheld_weight_full(grid, stc, p, m)
        type(grid_type), intent(in) :: grid
            !! grid with nodal masses
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: p
            !! particle
        real(wp), intent(in) :: m
            !! particle mass [kg]
        integer :: c
        integer :: node(max_stencil_nodes)
        real(wp) :: w(max_stencil_nodes)
        logical :: held
        call particle_weights(stc, p, node, w)
        held = .false.
        unheld_weight_full = 0.0_wp
        do c = 1, stc%count
            if (w(c) <= 0.0_wp) cycle
            if (m*w(c) > 0.5_wp*grid%mass(node(c))) then
                held = .true.
            else
                unheld_weight_full = unheld_weight_full + w(c)
            end if
        end do
        if (.not. held) unheld_weight_full = 1.0_wp
    end function unheld_weight_full

    !> Deformation gradient increment I + dt L (the identity outside the first dim axes).
    pure function increment(gradv, dt, dim) result(dF)
        real(wp), intent(in) :: gradv(3, 3), dt
        integer, intent(in) :: dim
        real(wp) :: dF(3, 3)
        integer :: a
        dF = 0.0_wp
        do a = 1, 3
            dF(a, a) = 1.0_wp
        end do
        dF(1:dim, 1:dim) = dF(1:dim, 1:dim) + dt*gradv(1:dim, 1:dim)
    end function increment

end module mpm_transfer
