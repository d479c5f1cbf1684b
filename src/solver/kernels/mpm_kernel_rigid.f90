!> The rigid bodies of a step (materials of type "rigid", mpm_material_rigid): one velocity
!> for all the nodes a body's particles touch, and for its particles.
!>
!> The nodes of each body are a region of grid%region_node (mpm_motion::hold_regions). Along
!> the components a prescribed_motion entry holds, the nodal update moves them at the
!> prescribed velocity, as it does a box region's nodes (mpm_kernel_nodal); along the others
!> the body moves as one lump (the rigid-body algorithm of Anura3D, Al-Kafaji 2013): its
!> velocity is the momentum of its nodes over their mass, sum p_i / sum m_i, after the nodal
!> update (so the weight of the body, its loads and the forces of the material it touches
!> at those nodes move it), and every node of the body takes that velocity. The lump keeps
!> the momentum; the energy its impulse takes from the nodes is booked as stopped by the
!> constraints (energy_type%boundary). A free component along which a face holds one of the
!> body's nodes is held at zero: the body rests on the face. The particles of the body then
!> take the body's velocity exactly (FLIP would add the noise of the nodes it shares with the
!> material); the change of their kinetic energy is booked the same way. A body moves the
!> nodes whose cell it fills to a fifth at least (mpm_motion::hold_regions), and its particles
!> at its edges also reach nodes it does not move: after the moves they take the body's mean
!> displacement (body_particle_positions), so the body stays rigid.
module mpm_kernel_rigid
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type, node_owned
    use mpm_particles, only: particles_type
    implicit none
    private
    public :: move_bodies, body_particle_velocities, body_particle_positions, has_bodies

contains

    !> Whether the step has rigid bodies.
    pure logical function has_bodies(grid)
        type(grid_type), intent(in) :: grid
            !! the grid of the step

        has_bodies = .false.
        if (allocated(grid%region_rigid)) has_bodies = any(grid%region_rigid > 0)
    end function has_bodies

    !> Give every node of each rigid body the body's velocity. After the nodal update
    !> (`update`), the velocity is the lump of the updated momentum and is kept for the step
    !> (grid%body_velocity), the nodes' accelerations take the change, and `lost` is the
    !> energy the lump's impulse took; before it (the start velocities of USF) the lump of the
    !> mapped momentum; after it again (MUSL's remap) the kept velocity.
    subroutine move_bodies(grid, dt, update, lost)
        type(grid_type), intent(inout) :: grid
            !! the grid, after the nodal velocities or the nodal update
        real(wp), intent(in) :: dt
            !! time step [s]
        logical, intent(in) :: update
            !! after the nodal update (its velocities and accelerations)
        real(wp), intent(out) :: lost
            !! kinetic energy the lump took from the nodes (update only) [J]

        integer :: n, id, r, a, dim, nr
        real(wp), allocatable :: momentum(:, :), mass(:)
        logical, allocatable :: stopped(:, :)
        real(wp) :: v, v0

        lost = 0.0_wp
        if (.not. has_bodies(grid)) return
        dim = grid%dim
        nr = size(grid%region_rigid)
        if (update .or. .not. grid%bodies_moved) then
            allocate (momentum(dim, nr), mass(nr), stopped(dim, nr))
            momentum = 0.0_wp
            mass = 0.0_wp
            stopped = .false.
            do n = 1, grid%nregion_nodes
                r = grid%region_of(n)
                if (grid%region_rigid(r) == 0) cycle
                id = grid%region_node(n)
                ! a face that holds a free component of one of the body's nodes holds it
                stopped(:, r) = stopped(:, r) .or. (grid%constrained(:, id) .and. &
                    .not. grid%region_held(:, r))
                if (grid%mass(id) <= grid%small_mass) cycle
                momentum(:, r) = momentum(:, r) + grid%momentum(:, id)
                mass(r) = mass(r) + grid%mass(id)
            end do
            do r = 1, nr
                if (grid%region_rigid(r) == 0) cycle
                do a = 1, dim
                    if (grid%region_held(a, r)) then
                        grid%body_velocity(a, r) = grid%region_velocity(a, r)
                    else if (stopped(a, r) .or. mass(r) <= 0.0_wp) then
                        grid%body_velocity(a, r) = 0.0_wp
                    else
                        grid%body_velocity(a, r) = momentum(a, r)/mass(r)
                    end if
                end do
            end do
            if (update) grid%bodies_moved = .true.
        end if
        do n = 1, grid%nregion_nodes
            r = grid%region_of(n)
            if (grid%region_rigid(r) == 0) cycle
            id = grid%region_node(n)
            if (update .and. grid%mass(id) > grid%small_mass) then
                do a = 1, dim
                    if (grid%region_held(a, r)) cycle
                    ! the lump's impulse m (V - v) on a node whose velocity went from v0 to v
                    ! in the update; at the velocity the node moves with over the step,
                    ! (v0 + V) / 2, it works -m (V - v) (v0 + V) / 2 against the material
                    ! (the work of the forces is counted at the velocities the particles move
                    ! with)
                    v = grid%momentum(a, id)/grid%mass(id)
                    v0 = v - dt*grid%acceleration(a, id)
                    if (node_owned(grid, id)) lost = lost - 0.5_wp*grid%mass(id) &
                        *(grid%body_velocity(a, r) - v)*(v0 + grid%body_velocity(a, r))
                    grid%acceleration(a, id) = grid%acceleration(a, id) &
                        + (grid%body_velocity(a, r) - v)/dt
                end do
            end if
            grid%velocity(:, id) = grid%body_velocity(:, r)
            grid%momentum(:, id) = grid%mass(id)*grid%body_velocity(:, r)
        end do
    end subroutine move_bodies

    !> The particles of each rigid body take the body's velocity of the step; `change` is the
    !> kinetic energy that gives them (the caller adds it to theirs and books it as stopped
    !> by the constraints).
    subroutine body_particle_velocities(grid, particles, change)
        type(grid_type), intent(in) :: grid
            !! the grid after the step's nodal update
        type(particles_type), intent(inout) :: particles
            !! the particles after G2P
        real(wp), intent(out) :: change
            !! change of their kinetic energy [J]

        integer :: p, r, dim
        integer, allocatable :: body_of(:)

        change = 0.0_wp
        if (.not. has_bodies(grid)) return
        dim = grid%dim
        allocate (body_of(maxval(grid%region_rigid)))
        body_of = 0
        do r = 1, size(grid%region_rigid)
            if (grid%region_rigid(r) > 0) body_of(grid%region_rigid(r)) = r
        end do
        do p = 1, particles%n
            if (particles%material(p) < 1 .or. particles%material(p) > size(body_of)) cycle
            r = body_of(particles%material(p))
            if (r == 0) cycle
            change = change + 0.5_wp*particles%mass(p)*(sum(grid%body_velocity(:, r)**2) &
                - sum(particles%v(1:dim, p)**2))
            particles%v(1:dim, p) = grid%body_velocity(:, r)
            ! (APIC: a rigid body's velocity field is uniform)
            if (allocated(particles%affine)) particles%affine(:, :, p) = 0.0_wp
        end do
    end subroutine body_particle_velocities

    !> After the particles moved: each rigid body's particles take the mean displacement of
    !> the body (by mass). They move with the nodal velocities, and a particle at the body's
    !> edge also reaches nodes the body does not move (mpm_motion::hold_regions: the nodes it
    !> fills to a fifth); the mean keeps the body's motion, and the body stays rigid.
    subroutine body_particle_positions(grid, particles)
        type(grid_type), intent(in) :: grid
            !! the grid of the step
        type(particles_type), intent(inout) :: particles
            !! the particles after their moves (with their displacements u)

        integer :: p, r, dim, nr
        integer, allocatable :: body_of(:)
        real(wp), allocatable :: mean(:, :), mass(:)
        real(wp) :: shift(3)

        if (.not. has_bodies(grid) .or. .not. allocated(particles%u)) return
        dim = grid%dim
        nr = size(grid%region_rigid)
        allocate (body_of(maxval(grid%region_rigid)), mean(dim, nr), mass(nr))
        body_of = 0
        do r = 1, nr
            if (grid%region_rigid(r) > 0) body_of(grid%region_rigid(r)) = r
        end do
        mean = 0.0_wp
        mass = 0.0_wp
        do p = 1, particles%n
            if (particles%material(p) < 1 .or. particles%material(p) > size(body_of)) cycle
            r = body_of(particles%material(p))
            if (r == 0) cycle
            mean(:, r) = mean(:, r) + particles%mass(p)*particles%u(1:dim, p)
            mass(r) = mass(r) + particles%mass(p)
        end do
        do r = 1, nr
            if (mass(r) > 0.0_wp) mean(:, r) = mean(:, r)/mass(r)
        end do
        do p = 1, particles%n
            if (particles%material(p) < 1 .or. particles%material(p) > size(body_of)) cycle
            r = body_of(particles%material(p))
            if (r == 0) cycle
            shift(1:dim) = mean(:, r) - particles%u(1:dim, p)
            particles%x(1:dim, p) = particles%x(1:dim, p) + shift(1:dim)
            particles%u(1:dim, p) = mean(:, r)
        end do
    end subroutine body_particle_positions

end module mpm_kernel_rigid
