!> The particle and grid passes of one explicit step.
!>
!> Particle-to-grid (P2G) scatters mass, momentum and forces to the nodes; the nodal update
!> integrates the momentum with damping and boundary conditions; grid-to-particle (G2P)
!> gathers accelerations and velocities back; the stress update uses the nodal velocities
!> chosen by the scheme. Each pass is one procedure; the scheme (USF/USL/MUSL) only orders
!> them (see mpm_solver), except that USL without F-bar updates the stresses inside G2P (the
!> same nodal velocities, one gather instead of two). Every pass reads the stencils of the
!> step (mpm_stencil): the shape functions are evaluated once per step, and the grid work
!> covers the box of nodes the particles touch.
!>
!> Threads: the gathers (G2P, stress update) are parallel over particles; the scatters (P2G,
!> remap) sum each chunk of cell-sorted particles into its own buffer and fold the buffers
!> into the grid in chunk order; the nodal update is parallel over nodes; every sum over
!> particles or nodes (energies) is taken per chunk or block and the partial sums added in a
!> fixed order. A run gives the same bits with any number of threads.
module mpm_transfer
    use mpm_kinds, only: wp
    use mpm_strings, only: vector_text
    use mpm_error, only: error_type, fatal_error, exit_numerical
    use mpm_grid, only: grid_type, contact_index, node_owned
    use mpm_halo, only: halo_sum, halo_contact_gaps, halo_box
    use mpm_terrain, only: terrain_distance
    use mpm_particles, only: particles_type, particle_number
    use mpm_stencil, only: stencils_type, particle_nodes, max_nodes, axis_derivatives
    use mpm_material, only: material_holder_type, nwork_kinds
    use mpm_case, only: damping_local, bc_free
    implicit none
    private
    public :: p2g, nodal_velocity, integrate_nodes, g2p, motion_type, report_lost
    public :: update_stress, nstress_sums

    integer, parameter :: nstress_sums = 2*nwork_kinds
        !! sums of a stress pass: the work of the stresses over the step by work kind of the
        !! materials (1 : nwork_kinds, `work_*` of mpm_material), then the elastic energy
        !! stored in the particles at the end of the step by work kind [J]

    real(wp), parameter :: contact_tolerance = 1.0e-3_wp
        !! material closer to a frictional face than this fraction of dx touches it [-]
    real(wp), parameter :: load_smoothing = 0.1_wp
        !! weight of the newest step in the running mean of the normal contact impulse when
        !! grid%contact_time is 0 [-]
    integer, parameter :: full_gimp_3d = 1, full_gimp_2d = 2, full_linear_3d = 3, &
        full_linear_2d = 4, other_stencil = 5
        !! stencil kinds with loops of constant length (stencil_kind)
    integer, parameter :: gather_block = 256
        !! particles per block of the passes that only gather (load balance; the partial sums
        !! of a block are added in block order)

    !> Buffers of one scatter pass: per chunk, the node layers it touches (mpm_stencil).
    type :: scatter_type
        real(wp), allocatable :: mass(:)
        real(wp), allocatable :: momentum(:, :)
        real(wp), allocatable :: fint(:, :)
        real(wp), allocatable :: fext(:, :)
    end type scatter_type

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

    integer, parameter, public :: nodal_damping = 1, nodal_friction = 2, nnodal_sums = 2
        !! sums of the nodal update (integrate_nodes): work of local damping and of the
        !! friction of frictional faces and the terrain (positive: energy removed)

contains

    !> Scatter particle mass, momentum and body forces (with_mass) and the internal force
    !> (with_fint) to the nodes; the fields not scattered keep their values.
    !>
    !> f_int,i = - sum_p V_p sigma_p . grad N_i(x_p); in 2D only the in-plane components.
    !> Gravity is not scattered: the nodal update adds m_i g. Only the extra body force of
    !> drivers that prescribe one (particles%body_force) goes to grid%fext.
    subroutine p2g(grid, particles, stc, with_mass, with_fint, fbar)
        type(grid_type), intent(inout), target :: grid
            !! grid receiving the nodal sums
        type(particles_type), intent(in) :: particles
            !! particles
        type(stencils_type), intent(in) :: stc
            !! stencils, order and chunks of the step
        logical, intent(in) :: with_mass
            !! scatter mass, momentum and the extra body force
        logical, intent(in) :: with_fint
            !! scatter the internal force
        logical, intent(in) :: fbar
            !! F-bar: the internal force takes the pressure of each particle as the mean of its
            !! cell, the counterpart of the cell-averaged volume change of `update_stress`

        integer :: p, q, k, c, dim, ns, shift, fint_row, body_row, rows, mass_row
        real(wp) :: s(6), vs(6), xp(3), vp(3), aff(3, 3), bf(3)
        logical :: apic, body
        real(wp), allocatable :: cell_pv(:), cell_v(:), gaps(:)
        real(wp), pointer, contiguous :: buf(:, :)

        dim = grid%dim
        ns = particles%nstress
        apic = allocated(particles%affine) .and. with_mass
        body = allocated(particles%body_force) .and. with_mass
        if (with_fint .and. fbar) then
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
        rows = 0
        mass_row = 0
        if (with_mass) mass_row = 1
        if (with_mass) rows = 1 + dim
        fint_row = 0
        if (with_fint) fint_row = rows + 1
        if (with_fint) rows = rows + dim
        body_row = 0
        if (body) body_row = rows + 1
        if (body) rows = rows + dim
        call scatter_buffer(grid, rows, stc%chunk_offset(stc%nchunks + 1), buf)

        !$omp parallel do default(none) schedule(dynamic, 1) &
        !$omp shared(grid, particles, stc, buf, with_mass, with_fint, fbar, apic, body, &
        !$omp dim, ns, cell_pv, fint_row, body_row, mass_row) &
        !$omp private(k, q, p, shift, s, vs, xp, vp, aff, bf)
        do k = 1, stc%nchunks
            shift = stc%chunk_base(k)
            buf(:, stc%chunk_offset(k) + 1:stc%chunk_offset(k + 1)) = 0.0_wp
            xp = 0.0_wp
            vp = 0.0_wp
            aff = 0.0_wp
            bf = 0.0_wp
            s = 0.0_wp
            vs = 0.0_wp
            do q = stc%chunk_start(k), stc%chunk_start(k + 1) - 1
                p = stc%order(q)
                if (with_mass) then
                    vp(1:2) = particles%v(1:2, p)
                    if (dim == 3) vp(3) = particles%v(3, p)
                    if (apic) then
                        xp(1:dim) = particles%x(:, p)
                        aff(1:dim, 1:dim) = particles%affine(:, :, p)
                    end if
                    if (body) bf(1:dim) = particles%body_force(:, p)
                end if
                if (with_fint) then
                    ! copies of a size known here (a runtime-sized one calls memcpy)
                    if (ns == 4) then
                        s(1:4) = particles%stress(1:4, p)
                    else
                        s(1:6) = particles%stress(1:6, p)
                    end if
                    if (fbar) s(1:3) = s(1:3) + cell_pv(stc%cell(p)) - sum(s(1:3))/3.0_wp
                    vs = -particles%volume(p)*s
                end if
                call scatter_particle(stc, grid, p, shift, particles%mass(p), xp, vp, aff, apic, &
                    mass_row, mass_row + 1, vs, fint_row, bf, body_row, buf)
            end do
        end do
        !$omp end parallel do

        call fold(grid, stc, buf, with_mass, fint_row, body_row)
        ! the nodes shared with neighbouring images take their particles' part too
        call halo_sum(grid, with_mass, with_mass, with_fint, body)
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
            call halo_contact_gaps(grid)
        end if
    end subroutine p2g

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
    subroutine fold(grid, stc, buf, mass_rows, fint_row, body_row, only_momentum)
        type(grid_type), intent(inout) :: grid
        type(stencils_type), intent(in) :: stc
        real(wp), intent(in) :: buf(:, :)
        logical, intent(in) :: mass_rows
        integer, intent(in) :: fint_row, body_row
        logical, intent(in), optional :: only_momentum
            !! set the momentum only, from rows 1 : dim (the MUSL remap)

        integer :: layer, id, k, b, rows, dim, lo(3), hi(3), j, x, y, z, first, last, &
            box_lo(3), box_hi(3)
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
            box_lo = stc%box_lo
            box_hi = stc%box_hi
            call halo_box(grid, box_lo, box_hi)
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

    !> Middle index bound of a box for box_row: the y bound in 3D, 0 in 2D (the slowest axis,
    !> the outer loop, is y there).
    pure integer function box_middle(bound, dim)
        integer, intent(in) :: bound(3)
            !! lower or upper corner of the box (0-based node indices)
        integer, intent(in) :: dim
            !! space dimensions
        box_middle = 0
        if (dim == 3) box_middle = bound(2)
    end function box_middle

    !> The run of nodes x = lo(1) .. hi(1) of a box at index `layer` along the slowest axis and
    !> middle index j (y in 3D, unused in 2D): node indices first .. last and its y and z.
    pure subroutine box_row(grid, lo, hi, layer, j, first, last, y, z)
        type(grid_type), intent(in) :: grid
            !! the grid
        integer, intent(in) :: lo(3), hi(3)
            !! corners of the box (0-based node indices)
        integer, intent(in) :: layer, j
            !! index along the slowest axis; middle index (box_middle)
        integer, intent(out) :: first, last
            !! node indices of the run (1-based)
        integer, intent(out) :: y, z
            !! node coordinates of the run (0-based)

        if (grid%dim == 2) then
            y = layer
            z = 0
        else
            y = j
            z = layer
        end if
        first = 1 + lo(1) + grid%nn(1)*(y + grid%nn(2)*z)
        last = first + hi(1) - lo(1)
    end subroutine box_row

    !> Record, for the contact nodes (frictional faces, terrain) particle p maps to, the gap
    !> between the particle's domain and the face or surface (negative when it reaches past
    !> it), as the smallest so far.
    subroutine contact_gaps(grid, particles, stc, p, gaps)
        type(grid_type), intent(in) :: grid
            !! grid with its contact pairs
        type(particles_type), intent(in) :: particles
            !! particles
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: p
            !! particle
        real(wp), intent(inout) :: gaps(:)
            !! smallest gap of each contact pair so far [m]

        integer :: a, side, c, k, dim
        integer :: node(max_nodes)
        real(wp) :: gap, face, w(max_nodes), dw(3, max_nodes), x(3), d, n(3)
        logical :: have_nodes, found

        have_nodes = .false.
        dim = grid%dim
        if (allocated(grid%terrain)) then
            ! the terrain: the distance from the particle domain to the surface
            x = 0.0_wp
            x(1:dim) = particles%x(:, p)
            call terrain_distance(grid%terrain, x, found, d, n)
            if (found) then
                gap = d - sum(particles%lp(:, p)*abs(n(1:dim)))
                call particle_nodes(stc, p, node, w, dw)
                have_nodes = .true.
                do k = 1, stc%count
                    if (w(k) <= 0.0_wp) cycle
                    c = grid%terrain_pair(node(k))
                    if (c > 0) gaps(c) = min(gaps(c), gap)
                end do
            end if
        end if
        do a = 1, grid%dim
            do side = 1, 2
                if (grid%contact_offset(side, a) < 0) cycle
                if (side == 1) then
                    face = grid%origin(a)
                    gap = particles%x(a, p) - particles%lp(a, p) - face
                else
                    face = grid%origin(a) + grid%dx*real(grid%nn(a) - 1, wp)
                    gap = face - particles%x(a, p) - particles%lp(a, p)
                end if
                if (gap > 2.0_wp*grid%dx) cycle
                if (.not. have_nodes) then
                    call particle_nodes(stc, p, node, w, dw)
                    have_nodes = .true.
                end if
                do k = 1, stc%count
                    if (w(k) <= 0.0_wp) cycle
                    c = contact_index(grid, node(k), side, a)
                    if (c > 0) gaps(c) = min(gaps(c), gap)
                end do
            end do
        end do
    end subroutine contact_gaps

    !> Nodal velocity v_i = p_i / m_i with the boundary conditions applied.
    subroutine nodal_velocity(grid)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set

        integer :: i, layer, j, first, last, y, z
        real(wp) :: work

        call apply_contacts(grid, 0.0_wp, work)
        !$omp parallel do default(none) schedule(static) shared(grid) &
        !$omp private(i, layer, j, first, last, y, z)
        do layer = grid%active_lo(grid%dim), grid%active_hi(grid%dim)
            do j = box_middle(grid%active_lo, grid%dim), box_middle(grid%active_hi, grid%dim)
                call box_row(grid, grid%active_lo, grid%active_hi, layer, j, first, last, y, z)
                do i = first, last
                    if (grid%mass(i) > 0.0_wp) then
                        where (grid%constrained(:, i)) grid%momentum(:, i) = 0.0_wp
                        grid%velocity(:, i) = grid%momentum(:, i)/grid%mass(i)
                    else
                        grid%velocity(:, i) = 0.0_wp
                    end if
                end do
            end do
        end do
        !$omp end parallel do
    end subroutine nodal_velocity

    !> Advance the nodal momentum over dt with gravity, damping and boundary conditions.
    !>
    !> f = f_int + m_i g + f_ext (f_ext: extra body forces only). Local damping adds
    !> f_d = - alpha |f| sign(v) per component, f the unbalanced force and v the nodal velocity
    !> at the start of the step. Frictional faces then act on the updated velocities
    !> (apply_contacts). Returns the work of damping and of friction in this step
    !> (positive: energy removed), see nnodal_sums. The fixed components of the boundaries
    !> and the normal constraint of the contacts do no work: their reaction acts where the
    !> velocity of the end of the step, the one the particles move and strain with, is zero.
    subroutine integrate_nodes(grid, dt, gravity, damping, alpha, dissipated)
        type(grid_type), intent(inout) :: grid
            !! grid with mass, momentum and forces set
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        integer, intent(in) :: damping
            !! case%damping
        real(wp), intent(in) :: alpha
            !! local damping coefficient [-]
        real(wp), intent(out) :: dissipated(nnodal_sums)
            !! energy removed in this step by local damping and by contact friction [J]

        integer :: i, dim, layer, j, first, last, y, z, lo, hi
        real(wp) :: f(3), v0(3), fd(3), acc
        real(wp), allocatable :: partial(:)

        dim = grid%dim
        ! one partial sum per layer of the box (slowest axis), added in layer order: the same
        ! sums with any number of threads
        lo = grid%active_lo(dim)
        hi = grid%active_hi(dim)
        allocate (partial(lo:max(lo, hi)))
        partial = 0.0_wp
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(grid, dt, gravity, damping, alpha, dim, partial, lo, hi) &
        !$omp private(layer, j, first, last, y, z, i, f, v0, fd, acc)
        do layer = lo, hi
            acc = 0.0_wp
            do j = box_middle(grid%active_lo, dim), box_middle(grid%active_hi, dim)
                call box_row(grid, grid%active_lo, grid%active_hi, layer, j, first, last, y, z)
                do i = first, last
                    if (grid%mass(i) <= 0.0_wp) then
                        grid%momentum(:, i) = 0.0_wp
                        grid%acceleration(:, i) = 0.0_wp
                        grid%velocity(:, i) = 0.0_wp
                        cycle
                    end if
                    f(1:dim) = grid%fint(:, i) + grid%fext(:, i) + grid%mass(i)*gravity(1:dim)
                    v0(1:dim) = grid%momentum(:, i)/grid%mass(i)
                    ! Held components are zero in the nodal velocity of the start of the step as
                    ! well as of its end, so their acceleration is zero and the FLIP update leaves
                    ! the particle velocities beside a fixed or sliding face to the forces (as
                    ! Uintah does). Putting the removed mapped velocity into the acceleration
                    ! instead makes the manufactured solution less accurate (cpGIMP MUSL, 64
                    ! cells: 9.4e-5 m against 3.5e-5 m).
                    where (grid%constrained(:, i))
                        grid%momentum(:, i) = 0.0_wp
                        v0(1:dim) = 0.0_wp
                    end where
                    if (damping == damping_local) then
                        fd(1:dim) = -alpha*abs(f(1:dim))*sign(1.0_wp, v0(1:dim))
                        where (v0(1:dim) == 0.0_wp) fd(1:dim) = 0.0_wp
                        where (grid%constrained(:, i)) fd(1:dim) = 0.0_wp
                        f(1:dim) = f(1:dim) + fd(1:dim)
                        ! nodes shared with another image count on one of them
                        if (node_owned(grid, i)) acc = acc &
                            - dt*sum(fd(1:dim)*(v0(1:dim) + 0.5_wp*dt*f(1:dim)/grid%mass(i)))
                    end if
                    where (grid%constrained(:, i)) f(1:dim) = 0.0_wp
                    if (grid%mass(i) < grid%small_mass) f(1:dim) = 0.0_wp
                    grid%acceleration(:, i) = f(1:dim)/grid%mass(i)
                    grid%momentum(:, i) = grid%momentum(:, i) + dt*f(1:dim)
                    grid%velocity(:, i) = grid%momentum(:, i)/grid%mass(i)
                end do
            end do
            partial(layer) = acc
        end do
        !$omp end parallel do
        dissipated = 0.0_wp
        do layer = lo, hi
            dissipated(nodal_damping) = dissipated(nodal_damping) + partial(layer)
        end do
        if (grid%ncontacts > 0) then
            call apply_contacts(grid, dt, dissipated(nodal_friction))
            do i = 1, grid%ncontacts
                associate (id => grid%contact_node(i))
                    if (grid%mass(id) > 0.0_wp) grid%velocity(:, id) = grid%momentum(:, id) &
                        /grid%mass(id)
                end associate
            end do
        end if
    end subroutine integrate_nodes

    !> Coulomb friction on frictional faces, node by node.
    !>
    !> A face node is in contact when the material touches the face (P2G records the gap
    !> between the particle domains and the face) and moves into it: its normal velocity is
    !> removed, and the normal impulse that takes enters a running mean over about ten steps
    !> (contact_load). Friction then reduces the tangential velocity by at most
    !> mu * contact_load / m (to zero: sticking). A node moving away from the face is free
    !> (lift-off), and a node the material no longer touches takes no normal impulse.
    !>
    !> Why the running mean (found with the sliding-block test): the normal velocity of a
    !> face node carries the particles' numerical noise, so some steps the node moves away
    !> from the face and takes no impulse, and in others it takes more. Friction limited by
    !> the impulse of the same step then has no grip in the steps without one, and a block
    !> that should stick creeps down the slope; limited by the mean it sees the steady
    !> normal load. A two-sided normal constraint is no cure: the positive part of a noisy
    !> normal impulse is far larger than its mean, and friction locks sliding blocks.
    !>
    !> Acts on grid%momentum; when dt > 0 the velocity change also enters grid%acceleration,
    !> so the particles (FLIP update) see the contact force, and friction is applied; with
    !> dt = 0 only the normal constraint is (velocities remapped within a step).
    subroutine apply_contacts(grid, dt, work)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set
        real(wp), intent(in) :: dt
            !! time step [s]; 0 when only velocities are corrected
        real(wp), intent(out) :: work
            !! work of friction [J]: the friction impulse times the tangential velocity of
            !! the end of the step, m (v_n - v_new) . v_new (v_n: the velocity with the normal
            !! part removed), mu N ds for a slide ds; the normal impulse acts where the normal
            !! velocity is zero and does no work

        integer :: c, id, dim
        real(wp) :: v(3), vnew(3), vt(3), n(3), vn, vt_norm, factor, weight, v1(3)
        logical :: touching

        dim = grid%dim
        work = 0.0_wp
        do c = 1, grid%ncontacts
            id = grid%contact_node(c)
            if (grid%mass(id) <= 0.0_wp) then
                if (dt > 0.0_wp) grid%contact_load(c) = 0.0_wp
                cycle
            end if
            ! n: unit normal into the obstacle (a face: +-e_axis, exactly; the arithmetic
            ! below then gives the same bits as component-wise code)
            n(1:dim) = grid%contact_dir(:, c)
            v(1:dim) = grid%momentum(:, id)/grid%mass(id)
            vn = dot_product(v(1:dim), n(1:dim))
            touching = grid%contact_gap(c) <= contact_tolerance*grid%dx
            if (.not. touching) vn = 0.0_wp
            vnew(1:dim) = v(1:dim)
            if (vn > 0.0_wp) vnew(1:dim) = v(1:dim) - vn*n(1:dim)
            v1(1:dim) = vnew(1:dim)
            if (dt > 0.0_wp) then
                ! running mean over a fixed time, so that the friction does not depend on dt
                weight = load_smoothing
                if (grid%contact_time > 0.0_wp) weight = min(1.0_wp, dt/grid%contact_time)
                grid%contact_load(c) = (1.0_wp - weight)*grid%contact_load(c) &
                    + weight*max(vn, 0.0_wp)*grid%mass(id)
                vn = dot_product(vnew(1:dim), n(1:dim))
                vt(1:dim) = vnew(1:dim) - vn*n(1:dim)
                vt_norm = norm2(vt(1:dim))
                if (vt_norm > 0.0_wp) then
                    factor = max(0.0_wp, &
                        1.0_wp - grid%contact_mu(c)*grid%contact_load(c)/(grid%mass(id)*vt_norm))
                    vnew(1:dim) = factor*vt(1:dim) + vn*n(1:dim)
                end if
                grid%acceleration(:, id) = grid%acceleration(:, id) + (vnew(1:dim) - v(1:dim))/dt
            end if
            grid%momentum(:, id) = grid%mass(id)*vnew(1:dim)
            if (node_owned(grid, id)) work = work &
                + grid%mass(id)*dot_product(v1(1:dim) - vnew(1:dim), vnew(1:dim))
        end do
    end subroutine apply_contacts

    !> Gather nodal accelerations and velocities: v_p += dt sum N_i a_i (FLIP), and, unless
    !> `remap`, move the particle by dx_p = dt sum N_i v_i (the later passes of the step use
    !> the stencils of the start-of-step positions, not the positions).
    !>
    !> With `remap` (MUSL), the same pass maps the updated particle momentum back to the nodes
    !> (chunk buffers folded in a fixed order, as in p2g) and recomputes the nodal velocities.
    !> With `materials` (USL without F-bar, whose stress update uses the same nodal velocities
    !> as the moves), the same pass also updates the stresses: one gather per particle and step
    !> instead of two; the blocks and the order of the work sums are those of update_stress.
    subroutine g2p(grid, particles, stc, dt, flip, gravity, remap, motion, kinetic, materials, &
            strain_work)
        type(grid_type), intent(inout), target :: grid
            !! grid after the nodal update (momentum and velocity replaced with `remap`)
        type(particles_type), intent(inout) :: particles
            !! particles whose velocities are updated
        type(stencils_type), intent(in) :: stc
            !! stencils, order and chunks of the step
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: flip
            !! FLIP fraction of the velocity update (1: FLIP, 0: PIC) [-]
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration (potential energy of the moves) [m/s2]
        logical, intent(in) :: remap
            !! MUSL: scatter the updated momentum and recompute the nodal velocities; the
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

        integer :: k, q, p, dim, shift, ng, qlo, qhi
        real(wp) :: xp(3), vp(3), aff(3, 3), bf(3), vs(6), dx(3), gradv(3, 3), ke, &
            ldts(3, 3, gather_block), work(nstress_sums)
        logical :: apic, stress
        real(wp), allocatable :: partial(:, :), partial_ke(:)
        real(wp), pointer, contiguous :: buf(:, :)
        type(motion_type), allocatable :: moved(:)
        type(motion_type) :: mine

        dim = grid%dim
        apic = allocated(particles%affine)
        stress = present(materials) .and. .not. remap
        ! the remap scatters: chunks; otherwise only gathers: small blocks balance the threads
        ng = group_count(stc, remap)
        allocate (moved(ng), partial(nstress_sums, ng), partial_ke(ng))
        if (remap) then
            ! the momentum only: the nodal masses do not change
            call scatter_buffer(grid, dim, stc%chunk_offset(stc%nchunks + 1), buf)
        else
            call scatter_buffer(grid, 1, 1, buf)
        end if
        !$omp parallel do default(none) schedule(dynamic, 1) &
        !$omp shared(grid, particles, stc, dt, flip, gravity, remap, buf, dim, apic, moved, ng, &
        !$omp materials, stress, partial, partial_ke) &
        !$omp private(k, q, p, shift, xp, vp, aff, bf, vs, dx, qlo, qhi, mine, gradv, work, ldts, &
        !$omp ke)
        do k = 1, ng
            ! records and sums in private variables, stored once per group: neighbouring
            ! groups run on other threads, and their array entries share cache lines
            mine = motion_type()
            work = 0.0_wp
            ke = 0.0_wp
            call group_range(stc, remap, k, qlo, qhi)
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
            do q = qlo, qhi
                p = stc%order(q)
                call update_particle_velocity(grid, particles, stc, p, dt, flip, apic, &
                    .not. remap, stress, dx, gradv)
                ke = ke + 0.5_wp*particles%mass(p)*sum(particles%v(:, p)**2)
                if (.not. remap) call move_particle(grid, particles, p, dx(1:dim), gravity, mine)
                if (stress) ldts(:, :, q - qlo + 1) = dt*gradv
                if (remap) then
                    vp(1:dim) = particles%v(:, p)
                    if (apic) then
                        xp(1:dim) = particles%x(:, p)
                        aff(1:dim, 1:dim) = particles%affine(:, :, p)
                    end if
                    call scatter_particle(stc, grid, p, shift, particles%mass(p), xp, vp, aff, &
                        apic, 0, 1, vs, 0, bf, 0, buf)
                end if
            end do
            if (stress) call stress_block(particles, materials, stc, qlo, qhi, ldts, dt, dim, work)
            moved(k) = mine
            partial(:, k) = work
            partial_ke(k) = ke
        end do
        !$omp end parallel do
        call merge_motion(moved, motion)
        kinetic = 0.0_wp
        do k = 1, ng
            kinetic = kinetic + partial_ke(k)
        end do
        if (present(strain_work)) then
            strain_work = 0.0_wp
            do k = 1, ng
                strain_work = strain_work + partial(:, k)
            end do
        end if
        if (remap) then
            call fold(grid, stc, buf, .true., 0, 0, only_momentum=.true.)
            call halo_sum(grid, .false., .true., .false., .false.)
            call nodal_velocity(grid)
        end if
    end subroutine g2p

    !> The G2P update of one particle: velocity (FLIP, PIC blend or APIC) and the position
    !> increment dt sum N_i v_i; the velocity gradient too with `with_gradient` (or APIC).
    subroutine update_particle_velocity(grid, particles, stc, p, dt, flip, apic, need_v, &
            with_gradient, dx, gradv)
        type(grid_type), intent(in) :: grid
        type(particles_type), intent(inout) :: particles
        type(stencils_type), intent(in) :: stc
        integer, intent(in) :: p
        real(wp), intent(in) :: dt, flip
        logical, intent(in) :: apic, with_gradient
        logical, intent(in) :: need_v
            !! the increment dx is used (the particle moves in this pass)
        real(wp), intent(out) :: dx(3), gradv(3, 3)

        integer :: dim, c
        integer :: node(max_nodes)
        real(wp) :: a(3), v(3), w(max_nodes), dw(3, max_nodes), kept

        dim = grid%dim
        ! the MUSL remap (FLIP) needs the accelerations only: the particles move later
        call gather_particle(stc, p, grid%acceleration, grid%velocity, .not. apic, &
            need_v .or. apic .or. flip < 1.0_wp, apic .or. with_gradient, a, v, gradv)
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
            call particle_nodes(stc, p, node, w, dw)
            c = stc%count
            kept = unheld_weight(grid, particles%mass(p), c, node, w)
            if (kept >= 1.0_wp) then
                particles%affine(:, :, p) = gradv(1:dim, 1:dim)
            else if (kept > 0.0_wp) then
                particles%affine(:, :, p) = kept*gradv(1:dim, 1:dim)
            else
                particles%affine(:, :, p) = 0.0_wp
            end if
        else if (flip < 1.0_wp) then
            particles%v(:, p) = flip*(particles%v(:, p) + dt*a(1:dim)) + (1.0_wp - flip)*v(1:dim)
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
        real(wp), intent(in) :: dx(:)
            !! position increment (dim) [m]
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        type(motion_type), intent(inout) :: motion
            !! record of the moves of a chunk

        integer :: a, dim
        real(wp) :: x(3), lo, hi, jump

        dim = grid%dim
        jump = maxval(abs(dx))
        if (.not. (jump <= huge(1.0_wp))) jump = huge(1.0_wp)   ! not finite
        if (jump > motion%jump) then
            motion%jump = jump
            motion%jump_particle = p
            motion%jump_length = norm2(dx)
        end if
        x(1:dim) = particles%x(:, p) + dx
        do a = 1, dim
            lo = grid%origin(a)
            hi = grid%origin(a) + grid%dx*real(grid%nn(a) - 1, wp)
            if (grid%bc(1, a) /= bc_free .and. x(a) < lo) x(a) = lo
            if (grid%bc(2, a) /= bc_free .and. x(a) > hi) x(a) = hi
            if (.not. (x(a) >= lo .and. x(a) <= hi) .and. motion%lost == 0) motion%lost = p
        end do
        motion%potential = motion%potential - particles%mass(p) &
            *dot_product(gravity(1:dim), x(1:dim) - particles%x(:, p))
        if (allocated(particles%body_force)) motion%load_work = motion%load_work &
            + particles%mass(p)*dot_product(particles%body_force(:, p), x(1:dim) - particles%x(:, p))
        if (allocated(particles%u)) then
            particles%u(:, p) = particles%u(:, p) + (x(1:dim) - particles%x(:, p))
        end if
        particles%x(:, p) = x(1:dim)
    end subroutine move_particle

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
    !> V = det(F) V0; GIMP half-sizes lp = lp0 F_aa (contiguous particle GIMP). Returns the
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
            motion)
        type(grid_type), intent(in) :: grid
            !! grid with nodal velocities
        type(particles_type), intent(inout) :: particles
            !! particles to update
        type(stencils_type), intent(in) :: stc
            !! stencils, order and chunks of the step
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

        integer :: p, q, k, dim, a
        real(wp) :: gradv(3, 3), ldt(3, 3), dF(3, 3), jac, scale, v(3), a3(3), &
            ldts(3, 3, gather_block)
        integer :: ng, qlo, qhi
        real(wp), allocatable :: grads(:, :, :), vels(:, :), cell_old(:), cell_new(:), &
            partial(:, :)
        type(motion_type), allocatable :: moved(:)
        type(motion_type) :: mine
        real(wp) :: work(nstress_sums)
        logical :: move

        dim = grid%dim
        move = present(motion)
        if (fbar) then
            allocate (grads(3, 3, particles%n), vels(3, particles%n))
            allocate (cell_old(product(grid%ncells)), cell_new(product(grid%ncells)))
            !$omp parallel do default(none) schedule(static) &
            !$omp shared(grid, particles, stc, grads, vels) private(p, a3)
            do p = 1, particles%n
                call gather_particle(stc, p, grid%velocity, grid%velocity, .false., .true., .true., &
                    a3, &
                    vels(:, p), grads(:, :, p))
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
        ng = group_count(stc, .false.)
        allocate (partial(nstress_sums, ng), moved(ng))
        !$omp parallel do default(none) schedule(dynamic, 1) &
        !$omp shared(grid, particles, stc, materials, dt, dim, fbar, grads, vels, gravity, &
        !$omp cell_old, cell_new, move, moved, partial, ng) &
        !$omp private(k, q, p, gradv, v, ldt, dF, jac, a, scale, a3, qlo, qhi, work, mine, ldts)
        do k = 1, ng
            work = 0.0_wp
            mine = motion_type()
            call group_range(stc, .false., k, qlo, qhi)
            do q = qlo, qhi
                p = stc%order(q)
                if (fbar) then
                    gradv = grads(:, :, p)
                    v = vels(:, p)
                else
                    call gather_particle(stc, p, grid%velocity, grid%velocity, .false., .true., &
                        .true., &
                        a3, v, gradv)
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
                ldts(:, :, q - qlo + 1) = ldt
                if (move) call move_particle(grid, particles, p, dt*v(1:dim), gravity, mine)
            end do
            call stress_block(particles, materials, stc, qlo, qhi, ldts, dt, dim, work)
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
    end subroutine update_stress

    !> The stress update of the particles order(qlo : qhi) (a block of at most gather_block)
    !> for the increments ldt(:, :, j) = dt L of their velocity gradients (ldt(i, k) =
    !> dt d v_i / d x_k, particle order(qlo + j - 1)): strain increments D dt and spins W dt to
    !> the materials, one call per run of particles of the same material (update_stress_block:
    !> no call per particle for the simple ones), then F <- (I + ldt) F, V = det(F) V0,
    !> lp = lp0 F_aa; adds the work of the stresses over the step and the elastic energy
    !> the particles store at its end to `work` (by work kind of the materials, see
    !> nstress_sums), particle by particle in order.
    subroutine stress_block(particles, materials, stc, qlo, qhi, ldt, dt, dim, work)
        type(particles_type), intent(inout) :: particles
            !! particles
        type(material_holder_type), intent(in) :: materials(:)
            !! materials of the case
        type(stencils_type), intent(in) :: stc
            !! stencils (the particle order)
        integer, intent(in) :: qlo, qhi
            !! the block: order(qlo : qhi)
        real(wp), intent(in) :: ldt(3, 3, gather_block)
            !! dt times the velocity gradients (first dim rows and columns) [-]
        real(wp), intent(in) :: dt
            !! time step [s]
        integer, intent(in) :: dim
            !! space dimensions
        real(wp), intent(inout) :: work(nstress_sums)
            !! sums of (V sigma)_mid : d_eps, then of the stored elastic energy V w(sigma),
            !! by work kind [J]

        integer :: n, ns, j, j0, j1, p, a, mat
        integer :: kind(gather_block)
        real(wp) :: s(6, gather_block), sold(6, gather_block), de(6, gather_block), &
            om(3, gather_block), vold, jac, density(gather_block), w
        real(wp) :: st(particles%nstate, qhi - qlo + 1)

        n = qhi - qlo + 1
        ns = particles%nstress
        do j = 1, n
            p = stc%order(qlo + j - 1)
            de(1, j) = ldt(1, 1, j)
            de(2, j) = ldt(2, 2, j)
            de(4, j) = 0.5_wp*(ldt(1, 2, j) + ldt(2, 1, j))
            om(1, j) = 0.5_wp*(ldt(1, 2, j) - ldt(2, 1, j))
            if (dim == 3) then
                de(3, j) = ldt(3, 3, j)
                de(5, j) = 0.5_wp*(ldt(2, 3, j) + ldt(3, 2, j))
                de(6, j) = 0.5_wp*(ldt(3, 1, j) + ldt(1, 3, j))
                om(2, j) = 0.5_wp*(ldt(2, 3, j) - ldt(3, 2, j))
                om(3, j) = 0.5_wp*(ldt(3, 1, j) - ldt(1, 3, j))
            else
                de(3, j) = 0.0_wp
                om(2:3, j) = 0.0_wp
            end if
            ! copies of a size known here: a runtime-sized copy is a memcpy call per particle
            if (ns == 4) then
                s(1:4, j) = particles%stress(1:4, p)
            else
                s(1:6, j) = particles%stress(1:6, p)
            end if
            sold(:, j) = s(:, j)
            if (particles%nstate > 0) st(:, j) = particles%state(:, p)
        end do
        ! runs of particles of one material
        j0 = 1
        do while (j0 <= n)
            mat = particles%material(stc%order(qlo + j0 - 1))
            j1 = j0
            do while (j1 < n)
                if (particles%material(stc%order(qlo + j1)) /= mat) exit
                j1 = j1 + 1
            end do
            call materials(mat)%m%update_stress_block(j1 - j0 + 1, s(1:ns, j0:j1), &
                de(1:ns, j0:j1), om(:, j0:j1), dt, st(:, j0:j1))
            call materials(mat)%m%elastic_energy_block(j1 - j0 + 1, s(1:ns, j0:j1), &
                st(:, j0:j1), density(j0:j1))
            kind(j0:j1) = materials(mat)%m%work_kind()
            j0 = j1 + 1
        end do
        do j = 1, n
            p = stc%order(qlo + j - 1)
            if (ns == 4) then
                particles%stress(1:4, p) = s(1:4, j)
            else
                particles%stress(1:6, p) = s(1:6, j)
            end if
            if (particles%nstate > 0) particles%state(:, p) = st(:, j)
            if (allocated(particles%strain)) then
                particles%strain(:, p) = particles%strain(:, p) + de(1:ns, j)
            end if
            ! deformation gradient F <- (I + ldt) F, volume and particle domain
            if (dim == 2) then
                call deform_2d(particles%f(:, :, p), ldt(:, :, j), jac)
            else
                call deform_3d(particles%f(:, :, p), ldt(:, :, j), jac)
            end if
            vold = particles%volume(p)
            particles%volume(p) = jac*particles%volume0(p)
            do a = 1, dim
                particles%lp(a, p) = particles%lp0(a, p)*abs(particles%f(a, a, p))
            end do
            ! trapezoidal rule on V sigma (volume and stress at both ends of the step):
            ! second order in dt, also when the volume changes with the strain
            ! (V sigma)_mid : de, shear components twice (tensor components)
            w = 0.0_wp
            do a = 1, 3
                w = w + 0.5_wp*(vold*sold(a, j) + particles%volume(p)*s(a, j))*de(a, j)
            end do
            do a = 4, ns
                w = w + (vold*sold(a, j) + particles%volume(p)*s(a, j))*de(a, j)
            end do
            work(kind(j)) = work(kind(j)) + w
            work(nwork_kinds + kind(j)) = work(nwork_kinds + kind(j)) &
                + density(j)*particles%volume(p)
        end do
    end subroutine stress_block

    !> F <- (I + ldt) F in 2D and its determinant.
    pure subroutine deform_2d(f, ldt, jac)
        real(wp), intent(inout) :: f(2, 2)
            !! deformation gradient
        real(wp), intent(in) :: ldt(3, 3)
            !! dt times the velocity gradient
        real(wp), intent(out) :: jac
            !! det F
        real(wp) :: g(2, 2)
        integer :: b

        do b = 1, 2
            g(1, b) = f(1, b) + ldt(1, 1)*f(1, b) + ldt(1, 2)*f(2, b)
            g(2, b) = f(2, b) + ldt(2, 1)*f(1, b) + ldt(2, 2)*f(2, b)
        end do
        f = g
        jac = g(1, 1)*g(2, 2) - g(1, 2)*g(2, 1)
    end subroutine deform_2d

    !> F <- (I + ldt) F in 3D and its determinant.
    pure subroutine deform_3d(f, ldt, jac)
        real(wp), intent(inout) :: f(3, 3)
            !! deformation gradient
        real(wp), intent(in) :: ldt(3, 3)
            !! dt times the velocity gradient
        real(wp), intent(out) :: jac
            !! det F
        real(wp) :: g(3, 3)
        integer :: a, b

        do b = 1, 3
            do a = 1, 3
                g(a, b) = f(a, b) + ldt(a, 1)*f(1, b) + ldt(a, 2)*f(2, b) + ldt(a, 3)*f(3, b)
            end do
        end do
        f = g
        jac = determinant(g, 3)
    end subroutine deform_3d

    pure subroutine scatter_particle(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        type(stencils_type), intent(in) :: stc
        type(grid_type), intent(in) :: grid
        integer, intent(in) :: p, shift, fint_row, body_row
        real(wp), intent(in) :: m, xp(3), vp(3), aff(3, 3), vs(6), bf(3)
        logical, intent(in) :: apic
        integer, intent(in) :: mass_row, momentum_row
        real(wp), intent(inout) :: buf(:, :)

        select case (stencil_kind(stc))
        case (full_gimp_3d)
            call scatter_g3(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, vs, &
                fint_row, bf, body_row, buf)
        case (full_gimp_2d)
            call scatter_g2(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, vs, &
                fint_row, bf, body_row, buf)
        case (full_linear_3d)
            call scatter_l3(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, vs, &
                fint_row, bf, body_row, buf)
        case (full_linear_2d)
            call scatter_l2(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, vs, &
                fint_row, bf, body_row, buf)
        case default
            call scatter_any(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, vs, &
                fint_row, bf, body_row, buf, stc%nper(1), stc%nper(2), stc%nper(3))
        end select
    end subroutine scatter_particle

    !> scatter_particle for full stencils, cpGIMP in 3D.
    pure subroutine scatter_g3(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        integer, parameter :: n1 = 3, n2 = 3, n3 = 3
        include "mpm_transfer_scatter.inc"
    end subroutine scatter_g3

    !> scatter_particle for full stencils, cpGIMP in 2D.
    pure subroutine scatter_g2(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        integer, parameter :: n1 = 3, n2 = 3, n3 = 1
        include "mpm_transfer_scatter.inc"
    end subroutine scatter_g2

    !> scatter_particle for full stencils, linear in 3D.
    pure subroutine scatter_l3(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        integer, parameter :: n1 = 2, n2 = 2, n3 = 2
        include "mpm_transfer_scatter.inc"
    end subroutine scatter_l3

    !> scatter_particle for full stencils, linear in 2D.
    pure subroutine scatter_l2(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf)
        integer, parameter :: n1 = 2, n2 = 2, n3 = 1
        include "mpm_transfer_scatter.inc"
    end subroutine scatter_l2

    !> scatter_particle for any stencil (an axis of the grid with fewer nodes than the shape
    !> function touches).
    pure subroutine scatter_any(stc, grid, p, shift, m, xp, vp, aff, apic, mass_row, momentum_row, &
            vs, fint_row, bf, body_row, buf, n1, n2, n3)
        integer, intent(in) :: n1, n2, n3
        include "mpm_transfer_scatter.inc"
    end subroutine scatter_any


    !> APIC: the parts C_p(:, a) (x_i,a - x_p,a) of the node velocity, per axis and node.
    pure subroutine apic_terms(stc, grid, p, xp, aff, cx, cy, cz)
        type(stencils_type), intent(in) :: stc
        type(grid_type), intent(in) :: grid
        integer, intent(in) :: p
        real(wp), intent(in) :: xp(3), aff(3, 3)
        real(wp), intent(out) :: cx(3, 3), cy(3, 3), cz(3, 3)

        integer :: i
        real(wp) :: r

        cx = 0.0_wp
        cy = 0.0_wp
        cz = 0.0_wp
        do i = 1, stc%nper(1)
            r = grid%origin(1) + grid%dx*real(stc%first(1, p) + i - 1, wp) - xp(1)
            cx(:, i) = aff(:, 1)*r
        end do
        do i = 1, stc%nper(2)
            r = grid%origin(2) + grid%dx*real(stc%first(2, p) + i - 1, wp) - xp(2)
            cy(:, i) = aff(:, 2)*r
        end do
        if (stc%dim == 3) then
            do i = 1, stc%nper(3)
                r = grid%origin(3) + grid%dx*real(stc%first(3, p) + i - 1, wp) - xp(3)
                cz(:, i) = aff(:, 3)*r
            end do
        end if
    end subroutine apic_terms

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

        select case (stencil_kind(stc))
        case (full_gimp_3d)
            call gather_g3(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case (full_gimp_2d)
            call gather_g2(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case (full_linear_3d)
            call gather_l3(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case (full_linear_2d)
            call gather_l2(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        case default
            call gather_any(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
                stc%nper(1), stc%nper(2), stc%nper(3))
        end select
    end subroutine gather_particle

    !> gather_particle for full stencils, cpGIMP in 3D.
    pure subroutine gather_g3(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        integer, parameter :: n1 = 3, n2 = 3, n3 = 3
        include "mpm_transfer_gather.inc"
    end subroutine gather_g3

    !> gather_particle for full stencils, cpGIMP in 2D.
    pure subroutine gather_g2(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        integer, parameter :: n1 = 3, n2 = 3, n3 = 1
        include "mpm_transfer_gather.inc"
    end subroutine gather_g2

    !> gather_particle for full stencils, linear in 3D.
    pure subroutine gather_l3(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        integer, parameter :: n1 = 2, n2 = 2, n3 = 2
        include "mpm_transfer_gather.inc"
    end subroutine gather_l3

    !> gather_particle for full stencils, linear in 2D.
    pure subroutine gather_l2(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient)
        integer, parameter :: n1 = 2, n2 = 2, n3 = 1
        include "mpm_transfer_gather.inc"
    end subroutine gather_l2

    !> gather_particle for any stencil (an axis of the grid with fewer nodes than the shape
    !> function touches).
    pure subroutine gather_any(stc, p, fa, fv, with_a, with_v, with_gradient, a, v, gradient, &
            n1, n2, n3)
        integer, intent(in) :: n1, n2, n3
        include "mpm_transfer_gather.inc"
    end subroutine gather_any


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

    !> Which constant-length loops a step's stencils can use: full cpGIMP or linear stencils
    !> in 2D or 3D, or another (an axis of the grid with fewer nodes than the shape touches).
    pure integer function stencil_kind(stc)
        type(stencils_type), intent(in) :: stc
        stencil_kind = other_stencil
        if (stc%dim == 3 .and. stc%count == 27) stencil_kind = full_gimp_3d
        if (stc%dim == 2 .and. stc%count == 9) stencil_kind = full_gimp_2d
        if (stc%dim == 3 .and. stc%count == 8) stencil_kind = full_linear_3d
        if (stc%dim == 2 .and. stc%count == 4) stencil_kind = full_linear_2d
    end function stencil_kind

    !> The weight of a particle of mass m on the nodes of its stencil that it does not hold
    !> (it holds a node with more than half of its mass); exactly 1 when it holds none, 0 when
    !> it is alone on its nodes.
    pure real(wp) function unheld_weight(grid, m, count, node, w)
        type(grid_type), intent(in) :: grid
            !! grid with nodal masses
        real(wp), intent(in) :: m
            !! particle mass [kg]
        integer, intent(in) :: count
            !! nodes of the stencil
        integer, intent(in) :: node(:)
            !! nodes
        real(wp), intent(in) :: w(:)
            !! weights
        integer :: c
        logical :: held
        held = .false.
        unheld_weight = 0.0_wp
        do c = 1, count
            if (w(c) <= 0.0_wp) cycle
            if (m*w(c) > 0.5_wp*grid%mass(node(c))) then
                held = .true.
            else
                unheld_weight = unheld_weight + w(c)
            end if
        end do
        if (.not. held) unheld_weight = 1.0_wp
    end function unheld_weight

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

    !> Determinant of a 2x2 or 3x3 matrix.
    pure real(wp) function determinant(m, dim)
        real(wp), intent(in) :: m(:, :)
        integer, intent(in) :: dim
        if (dim == 2) then
            determinant = m(1, 1)*m(2, 2) - m(1, 2)*m(2, 1)
        else
            determinant = m(1, 1)*(m(2, 2)*m(3, 3) - m(2, 3)*m(3, 2)) &
                - m(1, 2)*(m(2, 1)*m(3, 3) - m(2, 3)*m(3, 1)) &
                + m(1, 3)*(m(2, 1)*m(3, 2) - m(2, 2)*m(3, 1))
        end if
    end function determinant

end module mpm_transfer
