!> Contacts of the material with frictional faces and the terrain: the gap of each contact
!> pair from the particle domains (P2G) and the no-penetration and Coulomb friction
!> constraints on the nodal momentum (nodal update).
module mpm_kernel_contact
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type, contact_index, node_owned
    use mpm_terrain, only: terrain_distance
    use mpm_particles, only: particles_type
    use mpm_particle_domain, only: domain_half_sizes
    use mpm_stencil, only: stencils_type, particle_weights
    use mpm_shape, only: max_stencil_nodes
    implicit none
    private
    public :: apply_contacts, contact_gaps, keep_contact_start, contact_particle_work

    real(wp), parameter :: contact_tolerance = 1.0e-3_wp
        !! material closer to a frictional face than this fraction of dx touches it [-]
    real(wp), parameter :: load_smoothing = 0.1_wp
        !! weight of the newest step in the running mean of the normal contact impulse when
        !! grid%contact_time is 0 [-]

contains

    !> Coulomb friction on frictional faces, node by node.
    !>
    !> A face node is in contact when the material touches the face (P2G records the gap
    !> between the particle domains and the face) and moves into it faster than it closes the
    !> gap over the step: the normal velocity beyond gap / step is removed, and the normal
    !> impulse that takes enters a running mean over about ten steps
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
    !> Why gap / step (found with the sticking block of test_sliding_block): removing all the
    !> normal velocity into the face of every node within the gap tolerance, while a node
    !> moving out is free, rectifies the ringing of a block resting on the face: the moves
    !> out pass, the moves back in are stopped, and the block climbs to the tolerance
    !> (0.001 dx) and hovers there, its floor nodes half out of contact. That made the
    !> sticking block creep (0.21 mm in 0.5 s) and created the potential energy of the
    !> lift (2.7 mJ, 20 % of the work of gravity).
    !>
    !> Acts on grid%momentum; when dt > 0 the velocity change also enters grid%acceleration,
    !> so the particles (FLIP update) see the contact force, friction is applied and its
    !> impulse kept (grid%contact_friction); with dt = 0 only the normal constraint is
    !> (velocities remapped within a step), and the work is that of the kept friction
    !> impulse at the remapped velocities, those the particles slide with (MUSL).
    subroutine apply_contacts(grid, dt, step, work, stopped)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set
        real(wp), intent(in) :: dt
            !! time step [s]; 0 when only velocities are corrected
        real(wp), intent(in) :: step
            !! time step the corrected velocities move the particles over [s]; 0 if unknown
        real(wp), intent(out) :: work
            !! work of friction [J]: the friction impulse of the step, m (v_n - v_new) (v_n:
            !! the velocity with the normal part removed), times the velocity the node moves
            !! with (v_new, or the remapped one when dt = 0), mu N ds for a slide ds; a node
            !! that left the face in the remap does none
        real(wp), intent(out) :: stopped
            !! kinetic energy the normal constraint stops [J]: 1/2 m v_s^2 for the normal
            !! velocity v_s into the obstacle (beyond gap / step) that the node brought into
            !! the step, v - dt a (a: the acceleration of the step's forces), where the
            !! constraint acts; the velocity the forces add within the step is stopped too, but
            !! the particles never move with it, and the forces' work (at the velocity of the
            !! moves) never counted it

        integer :: c, id, dim
        real(wp) :: v(3), vnew(3), vt(3), n(3), vn, vt_norm, factor, weight, v1(3), brought, removed
        logical :: touching

        dim = grid%dim
        work = 0.0_wp
        stopped = 0.0_wp
        do c = 1, grid%ncontacts
            id = grid%contact_node(c)
            if (grid%mass(id) <= grid%small_mass) then
                if (dt > 0.0_wp) then
                    grid%contact_load(c) = 0.0_wp
                    grid%contact_friction(:, c) = 0.0_wp
                    grid%contact_impulse(:, c) = 0.0_wp
                end if
                cycle
            end if
            ! n: unit normal into the obstacle (a face: +-e_axis, exactly; the arithmetic
            ! below then gives the same bits as component-wise code)
            n(1:dim) = grid%contact_dir(:, c)
            v(1:dim) = grid%momentum(:, id)/grid%mass(id)
            vn = dot_product(v(1:dim), n(1:dim))
            touching = grid%contact_gap(c) <= contact_tolerance*grid%dx
            if (.not. touching) vn = 0.0_wp
            ! the node may close the gap over the step: only the normal velocity beyond it is
            ! removed (symmetric about the face, no ratchet off it). Domain faces only: the gap
            ! to an STL terrain (contact_axis 0) comes from a distance query whose last bits
            ! depend on the image's part of the grid, and used as a velocity it made a terrain
            ! slide on 2 images differ from the serial run (stress 5e-8 relative; the terrain
            ! keeps the tolerance test alone, as before)
            if (touching .and. step > 0.0_wp .and. grid%contact_axis(c) > 0) then
                vn = vn - max(grid%contact_gap(c), 0.0_wp)/step
            end if
            vnew(1:dim) = v(1:dim)
            if (vn > 0.0_wp) vnew(1:dim) = v(1:dim) - vn*n(1:dim)
            ! the normal velocity removed that the node brought into the step (not the one
            ! the step's forces added)
            removed = max(vn, 0.0_wp)
            brought = 0.0_wp
            if (vn > 0.0_wp) brought = max(0.0_wp, vn - dt*dot_product(grid%acceleration(:, id), &
                n(1:dim)))
            if (vn > 0.0_wp .and. node_owned(grid, id)) stopped = stopped &
                + 0.5_wp*grid%mass(id)*brought**2
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
            if (dt > 0.0_wp) then
                grid%contact_friction(:, c) = grid%mass(id)*(v1(1:dim) - vnew(1:dim))
                grid%contact_impulse(:, c) = -grid%mass(id)*min(brought, removed) &
                    *n(1:dim)
            else if (.not. touching) then
                ! the node left the face: its move is no slip on it
                cycle
            end if
            ! the friction impulse of the step times the velocity the node moves with: that
            ! of the nodal update, or of the remap when there is one (MUSL)
            if (node_owned(grid, id)) work = work &
                + dot_product(grid%contact_friction(:, c), vnew(1:dim))
        end do
    end subroutine apply_contacts

    !> Keep the momentum of each contact pair's node as P2G gave it, before the nodal update
    !> (contact_particle_work).
    subroutine keep_contact_start(grid)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set by P2G

        integer :: c

        do c = 1, grid%ncontacts
            grid%contact_start(:, c) = grid%momentum(:, grid%contact_node(c))
        end do
    end subroutine keep_contact_start

    !> The kinetic energy the contact impulses of the step's nodal update take from the
    !> particles when G2P adds the nodal accelerations to their velocities (FLIP), split into
    !> friction and normal constraint (positive: energy removed) [J].
    !>
    !> FLIP changes the velocity of particle p by dv_p = sum_i N_ip dv_i, so its kinetic energy
    !> by m_p vm_p . dv_p exactly, vm_p the mean of its velocities before and after. Summed over
    !> the particles, the share of a nodal change dv_i is dv_i . sum_p N_ip m_p vm_p: the
    !> impulse J_i = m_i dv_i times the mean of the momenta P2G maps to the node from the old
    !> and the new particle velocities, over m_i. Called with the MUSL remap momentum on the
    !> grid this is exact for the particles (the same weights map both); without a remap (USL,
    !> USF) the nodal momentum after the update stands for the new one. As for the nodes
    !> (apply_contacts' `stopped`), the normal impulse booked is the one that stops the normal
    !> velocity a node brought into the step: the velocity the step's forces add and the
    !> constraint takes away again (gravity on material resting on the terrain) never moves
    !> the particles, and the forces' work is booked at the moves
    !> (inputs/landslide_terrain.json at t = 2 s: residual +28 J of 7 347 J of gravity work
    !> so, +86 J with the whole normal impulse, -414 J with none).
    subroutine contact_particle_work(grid, friction, stopped)
        type(grid_type), intent(in) :: grid
            !! grid with the momentum of the new particle velocities (remap) or of the update
        real(wp), intent(out) :: friction
            !! kinetic energy the friction impulses took from the particles [J]
        real(wp), intent(out) :: stopped
            !! kinetic energy the normal constraint took from the particles [J]

        integer :: c, id, dim
        real(wp) :: vm(3)

        dim = grid%dim
        friction = 0.0_wp
        stopped = 0.0_wp
        do c = 1, grid%ncontacts
            id = grid%contact_node(c)
            if (grid%mass(id) <= grid%small_mass .or. .not. node_owned(grid, id)) cycle
            vm(1:dim) = 0.5_wp*(grid%contact_start(:, c) + grid%momentum(:, id))/grid%mass(id)
            ! contact_friction is minus the friction's change of momentum
            friction = friction + dot_product(grid%contact_friction(:, c), vm(1:dim))
            stopped = stopped - dot_product(grid%contact_impulse(:, c), vm(1:dim))
        end do
    end subroutine contact_particle_work

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
        integer :: node(max_stencil_nodes)
        real(wp) :: gap, face, w(max_stencil_nodes), x(3), d, n(3), lp(3)
        logical :: have_nodes, found

        have_nodes = .false.
        dim = grid%dim
        ! the particle domain's half-sizes, for the gaps of the contacts there are
        if (allocated(grid%terrain) .or. any(grid%contact_offset >= 0)) then
            call domain_half_sizes(particles%f(:, :, p), particles%lp0(:, p), dim, lp(1:dim))
        end if
        if (allocated(grid%terrain)) then
            ! the terrain: the distance from the particle domain to the surface
            x = 0.0_wp
            x(1:dim) = particles%x(:, p)
            call terrain_distance(grid%terrain, x, found, d, n)
            if (found) then
                gap = d - sum(lp(1:dim)*abs(n(1:dim)))
                call particle_weights(stc, p, node, w)
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
                    gap = particles%x(a, p) - lp(a) - face
                else
                    face = grid%origin(a) + grid%dx*real(grid%nn(a) - 1, wp)
                    gap = face - particles%x(a, p) - lp(a)
                end if
                if (gap > 2.0_wp*grid%dx) cycle
                if (.not. have_nodes) then
                    call particle_weights(stc, p, node, w)
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

end module mpm_kernel_contact
