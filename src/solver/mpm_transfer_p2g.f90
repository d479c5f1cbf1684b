!> The scatters of the particle passes: particle-to-grid (P2G) of mass, momentum and forces
!> (mpm_kernel_scatter), the P2G of the next step inside the last pass of a one-pass step, and
!> the XPIC pass of a nodal field through the particles; with the chunk buffers they sum into
!> and their fold into the grid, which the passes of mpm_transfer share.
!>
!> Threads: each chunk of cell-sorted particles sums into its own buffer, and the buffers
!> are folded into the grid in chunk order: a run gives the same bits with any number of
!> threads.
module mpm_transfer_p2g
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    use mpm_particles, only: particles_type
    use mpm_stencil, only: stencils_type, restencil, chunk_holds, cut_chunks
    use mpm_shape, only: shape_type
    use mpm_kernel_stress, only: gather_block
    use mpm_kernel_scatter, only: scatter_particle
    use mpm_kernel_gather, only: gather_particle
    use mpm_kernel_contact, only: contact_gaps
    use mpm_kernel_nodal, only: box_middle, box_row
    implicit none
    private
    public :: p2g, p2g_options_type, map_through_particles
    public :: next_scatter_type, open_next_scatter, next_scatter, close_next_scatter
    public :: scatter_buffer, fold, group_count, group_range

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
end module mpm_transfer_p2g
