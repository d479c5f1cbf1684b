!> The rigid bodies of a step (materials of type "rigid", mpm_material_rigid): one velocity
!> for the nodes of a body, and for its particles.
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
!> take one velocity (FLIP would add the noise of the nodes it shares with the
!> material, and at its edges the nodes it does not move), by the mean of theirs along its
!> free components (the change of their kinetic energy, never a gain there, is booked the
!> same way). A body moves the nodes whose cell it fills to a fifth at least
!> (mpm_motion::hold_regions); after the moves its particles take its displacement, that of
!> the step's start plus dt times its velocity (body_particle_positions), and stay
!> undeformed, so the body stays rigid.
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
                        ! the face that stops the body takes the impulse that does: its reaction
                        if (update .and. stopped(a, r)) call stopping_face(r, a)
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
    contains

        !> Book the impulse that stops body r along axis a (its owned nodes' momentum, minus)
        !> on the first face that holds a as a component of one of its nodes.
        subroutine stopping_face(r, a)
            integer, intent(in) :: r, a

            integer :: k, node
            real(wp) :: owned

            owned = 0.0_wp
            do k = 1, grid%nregion_nodes
                if (grid%region_of(k) /= r) cycle
                node = grid%region_node(k)
                if (grid%mass(node) <= grid%small_mass .or. .not. node_owned(grid, node)) cycle
                owned = owned - grid%momentum(a, node)
            end do
            do k = 1, grid%nheld
                if (grid%region_mark(grid%held_node(k)) /= r) cycle
                if (.not. grid%held_mask(a, k)) cycle
                associate (side => grid%held_face(1, k), axis => grid%held_face(2, k))
                    grid%face_impulse(a, side, axis) = grid%face_impulse(a, side, axis) + owned
                end associate
                return
            end do
            ! (no such face: the body's own reaction)
            grid%region_impulse(a, r) = grid%region_impulse(a, r) + owned
        end subroutine stopping_face
    end subroutine move_bodies

    !> The particles of each rigid body take one velocity after G2P: along the held
    !> components the prescribed one, along the others the mean of their G2P velocities by
    !> mass (the momentum G2P gave them is kept, and the kinetic energy can only drop: the
    !> particles at the body's edge also take the acceleration of nodes the body does not
    !> move). That velocity becomes the body's for the rest of the step (MUSL's remap, the
    !> moves: body_particle_positions); `change` is the kinetic energy it gives them.
    subroutine body_particle_velocities(grid, particles, change)
        type(grid_type), intent(inout) :: grid
            !! the grid after the step's nodal update
        type(particles_type), intent(inout) :: particles
            !! the particles after G2P
        real(wp), intent(out) :: change
            !! change of their kinetic energy [J]

        integer :: p, r, dim, nr
        integer, allocatable :: body_of(:)
        real(wp), allocatable :: momentum(:, :), mass(:)

        change = 0.0_wp
        if (.not. has_bodies(grid)) return
        dim = grid%dim
        nr = size(grid%region_rigid)
        body_of = bodies_of_materials(grid)
        allocate (momentum(dim, nr), mass(nr))
        momentum = 0.0_wp
        mass = 0.0_wp
        do p = 1, particles%n
            r = body_of_particle(p)
            if (r == 0) cycle
            momentum(:, r) = momentum(:, r) + particles%mass(p)*particles%v(1:dim, p)
            mass(r) = mass(r) + particles%mass(p)
        end do
        do r = 1, nr
            if (grid%region_rigid(r) == 0 .or. mass(r) <= 0.0_wp) cycle
            where (.not. grid%region_held(:, r)) grid%body_velocity(:, r) = momentum(:, r)/mass(r)
        end do
        do p = 1, particles%n
            r = body_of_particle(p)
            if (r == 0) cycle
            change = change + 0.5_wp*particles%mass(p)*(sum(grid%body_velocity(:, r)**2) &
                - sum(particles%v(1:dim, p)**2))
            particles%v(1:dim, p) = grid%body_velocity(:, r)
            ! (APIC: a rigid body's velocity field is uniform)
            if (allocated(particles%affine)) particles%affine(:, :, p) = 0.0_wp
        end do
    contains
        !> The body of particle p, 0 for none.
        pure integer function body_of_particle(p)
            integer, intent(in) :: p

            body_of_particle = 0
            if (particles%material(p) >= 1 .and. particles%material(p) <= size(body_of)) then
                body_of_particle = body_of(particles%material(p))
            end if
        end function body_of_particle
    end subroutine body_particle_velocities

    !> The region of each rigid material's body (0: none), by material index.
    pure function bodies_of_materials(grid) result(body_of)
        type(grid_type), intent(in) :: grid
            !! the grid of the step
        integer, allocatable :: body_of(:)

        integer :: r

        allocate (body_of(maxval(grid%region_rigid)))
        body_of = 0
        do r = 1, size(grid%region_rigid)
            if (grid%region_rigid(r) > 0) body_of(grid%region_rigid(r)) = r
        end do
    end function bodies_of_materials

    !> After the particles moved: each rigid body's particles take the displacement of the
    !> body, its displacement at the step's start (grid%body_start) plus dt times its velocity
    !> (the particles at its edge moved with nodes it does not move too), and stay undeformed:
    !> F = I, the volume of their start.
    subroutine body_particle_positions(grid, particles, dt)
        type(grid_type), intent(in) :: grid
            !! the grid of the step
        type(particles_type), intent(inout) :: particles
            !! the particles after their moves (with their displacements u)
        real(wp), intent(in) :: dt
            !! time step [s]

        integer :: p, r, dim, a
        integer, allocatable :: body_of(:)
        real(wp) :: target(3)

        if (.not. has_bodies(grid) .or. .not. allocated(particles%u)) return
        dim = grid%dim
        body_of = bodies_of_materials(grid)
        do p = 1, particles%n
            if (particles%material(p) < 1 .or. particles%material(p) > size(body_of)) cycle
            r = body_of(particles%material(p))
            if (r == 0) cycle
            target(1:dim) = grid%body_start(:, r) + dt*grid%body_velocity(:, r)
            particles%x(1:dim, p) = particles%x(1:dim, p) + target(1:dim) - particles%u(1:dim, p)
            particles%u(1:dim, p) = target(1:dim)
            particles%f(:, :, p) = 0.0_wp
            do a = 1, dim
                particles%f(a, a, p) = 1.0_wp
            end do
            particles%volume(p) = particles%volume0(p)
        end do
    end subroutine body_particle_positions

end module mpm_kernel_rigid
