!> The nodal update: nodal velocities from mass and momentum, and the momentum update of a
!> step with gravity, local damping, the boundary constraints and the contacts.
!>
!> The loops cover the box of nodes the last P2G wrote (grid%active_lo/active_hi), in
!> parallel over node layers of the slowest axis; the work of damping is summed per layer and
!> the layer sums added in order (the same bits with any number of threads).
module mpm_kernel_nodal
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type, node_owned
    use mpm_kernel_contact, only: apply_contacts
    implicit none
    private
    public :: nodal_velocity, integrate_nodes, box_middle, box_row, nodal_kinetic
    public :: nodal_damping, nodal_friction, nodal_boundary, nodal_faces, nodal_absorbed, &
        nodal_rigid, nnodal_sums

    integer, parameter :: nodal_damping = 1, nodal_friction = 2, nodal_boundary = 3, &
        nodal_faces = 4, nodal_absorbed = 5, nodal_rigid = 6, nnodal_sums = 6
        !! sums of the nodal update (integrate_nodes): work of local damping, of the friction
        !! of frictional faces and the terrain, and the kinetic energy the fixed components
        !! and the normal constraint of the contacts stop (positive: energy removed); the
        !! work of the velocity faces on the material (positive: energy given); the energy the
        !! faces that act on their nodes took (absorbing faces, mpm_step_passes::
        !! act_on_faces; positive: removed), booked with what the faces stop; the kinetic
        !! energy the rigid bodies' constraint takes from their nodes and particles
        !! (mpm_kernel_rigid; positive: removed), booked with it too


contains

    !> Nodal velocity v_i = p_i / m_i with the boundary conditions applied. The light nodes'
    !> momentum is folded into their masters before (it keeps nothing then) and their
    !> velocities slaved after, by the caller (mpm_halo: fold_light, slave_light).
    subroutine nodal_velocity(grid, step, friction_work)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set
        real(wp), intent(in) :: step
            !! time step the velocities move the particles over [s]
        real(wp), intent(out), optional :: friction_work
            !! work of the friction impulses of the step's nodal update at these velocities
            !! (a remap: the velocities the particles move with) [J]

        integer :: i, layer, j, first, last, y, z
        real(wp) :: work, stopped

        ! what the constraints stop here: the caller compares nodal_kinetic before and after
        call apply_contacts(grid, 0.0_wp, step, work, stopped)
        if (present(friction_work)) friction_work = work
        !$omp parallel do default(none) schedule(static) shared(grid) &
        !$omp private(i, layer, j, first, last, y, z)
        do layer = grid%active_lo(grid%dim), grid%active_hi(grid%dim)
            do j = box_middle(grid%active_lo, grid%dim), box_middle(grid%active_hi, grid%dim)
                call box_row(grid, grid%active_lo, grid%active_hi, layer, j, first, last, y, z)
                do i = first, last
                    if (grid%mass(i) > grid%small_mass) then
                        where (grid%constrained(:, i)) grid%momentum(:, i) = 0.0_wp
                        grid%velocity(:, i) = grid%momentum(:, i)/grid%mass(i)
                    else
                        grid%velocity(:, i) = 0.0_wp
                    end if
                end do
            end do
        end do
        !$omp end parallel do
        call set_prescribed(grid)
    end subroutine nodal_velocity

    !> Kinetic energy of the nodal momentum, sum_i |p_i|^2 / (2 m_i) over the nodes of the
    !> active box that are not empty (nodes shared with another image on one of them) [J]:
    !> after P2G and after the nodal update, the two ends of the grid's part of the step.
    real(wp) function nodal_kinetic(grid)
        type(grid_type), intent(in) :: grid
            !! grid with mass and momentum set

        integer :: i, layer, j, first, last, y, z, lo, hi
        real(wp) :: acc
        real(wp), allocatable :: partial(:)

        lo = grid%active_lo(grid%dim)
        hi = grid%active_hi(grid%dim)
        allocate (partial(lo:max(lo, hi)))
        partial = 0.0_wp
        !$omp parallel do default(none) schedule(static) shared(grid, partial, lo, hi) &
        !$omp private(i, layer, j, first, last, y, z, acc)
        do layer = lo, hi
            acc = 0.0_wp
            do j = box_middle(grid%active_lo, grid%dim), box_middle(grid%active_hi, grid%dim)
                call box_row(grid, grid%active_lo, grid%active_hi, layer, j, first, last, y, z)
                do i = first, last
                    if (grid%mass(i) > grid%small_mass .and. node_owned(grid, i)) then
                        acc = acc + 0.5_wp*sum(grid%momentum(:, i)**2)/grid%mass(i)
                    end if
                end do
            end do
            partial(layer) = acc
        end do
        !$omp end parallel do
        nodal_kinetic = 0.0_wp
        do layer = lo, hi
            nodal_kinetic = nodal_kinetic + partial(layer)
        end do
    end function nodal_kinetic

    !> Kinetic energy of the held (fixed) velocity components of node i, sum |p_c|^2 / (2 m) [J].
    pure real(wp) function held_kinetic(grid, i)
        type(grid_type), intent(in) :: grid
            !! grid with mass and momentum set
        integer, intent(in) :: i
            !! node (not empty)
        held_kinetic = 0.5_wp*sum(merge(grid%momentum(:, i), 0.0_wp, grid%constrained(:, i))**2) &
            /grid%mass(i)
    end function held_kinetic

    !> The impulse the velocity faces give their nodes over the step, before the update: the
    !> one that holds the node's velocity against the forces on it, -dt f (f = f_int + f_ext +
    !> m g; damping does not act on held components), summed per face (grid%face_impulse),
    !> and its work, that impulse times the face's velocity v (the node moves at v).
    !>
    !> The mapped momentum p is set to m v at the start of the step, as a fixed face sets it
    !> to zero, and not booked: it is no force on the particles (the FLIP update leaves them
    !> to the forces). Booked, m v - p - dt f made the energy of test_velocity_face miss 1.1 %
    !> of the face's work and its reaction 1.3 % high; -dt f closes it to 2e-4.
    !>
    !> A face whose velocity changes in time (grid%face_varies: a seismic base) takes the node
    !> from v0 at the start of the step to v1 at its end: its impulse is m (v1 - v0) - dt f,
    !> and its work that impulse at the mean velocity (v0 + v1) / 2.
    subroutine prescribed_impulses(grid, dt, gravity, work, restart)
        type(grid_type), intent(inout) :: grid
            !! grid with mass, momentum and forces set
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        real(wp), intent(out) :: work
            !! work of the velocity faces on the material over the step [J]
        real(wp), intent(out) :: restart
            !! kinetic energy of the velocity faces' nodes at the faces' start velocities,
            !! 1/2 m |v0|^2 (each node once: its last face's) [J]

        integer :: n, id, dim, r
        real(wp) :: impulse(3), mean(3)

        dim = grid%dim
        work = 0.0_wp
        restart = 0.0_wp
        grid%face_impulse = 0.0_wp
        if (grid%keep_reaction) then
            if (allocated(grid%node_reaction)) then
                if (size(grid%node_reaction, 2) /= grid%nnodes) deallocate (grid%node_reaction)
            end if
            if (.not. allocated(grid%node_reaction)) allocate (grid%node_reaction(dim, grid%nnodes))
            grid%node_reaction = 0.0_wp
        end if
        do n = 1, grid%nprescribed
            id = grid%prescribed_node(n)
            if (grid%mass(id) <= grid%small_mass .or. .not. node_owned(grid, id)) cycle
            impulse(1:dim) = -dt*(grid%fint(:, id) + grid%fext(:, id) &
                + grid%mass(id)*gravity(1:dim))
            mean(1:dim) = grid%prescribed_velocity(:, n)
            if (grid%prescribed_varies) then
                if (grid%face_varies(grid%prescribed_face(1, n), grid%prescribed_face(2, n))) &
                    then
                    impulse(1:dim) = impulse(1:dim) + grid%mass(id) &
                        *(grid%prescribed_velocity(:, n) - grid%prescribed_start(:, n))
                    mean(1:dim) = 0.5_wp*(grid%prescribed_velocity(:, n) &
                        + grid%prescribed_start(:, n))
                end if
            end if
            ! (a component an earlier face holds is that face's reaction)
            associate (side => grid%prescribed_face(1, n), axis => grid%prescribed_face(2, n))
                grid%face_impulse(1:dim, side, axis) = grid%face_impulse(1:dim, side, axis) &
                    + merge(impulse(1:dim), 0.0_wp, grid%prescribed_mask(:, n))
            end associate
            if (grid%keep_reaction) grid%node_reaction(:, id) = grid%node_reaction(:, id) &
                + merge(impulse(1:dim), 0.0_wp, grid%prescribed_mask(:, n))/dt
            work = work + dot_product(impulse(1:dim), mean(1:dim))
            if (grid%prescribed_last(n)) then
                if (grid%prescribed_varies) then
                    restart = restart + 0.5_wp*grid%mass(id)*sum(grid%prescribed_start(:, n)**2)
                else
                    restart = restart + 0.5_wp*grid%mass(id)*sum(grid%prescribed_velocity(:, n)**2)
                end if
            end if
        end do
        ! the faces that hold components at zero: the force on those components (no work)
        do n = 1, grid%nheld
            id = grid%held_node(n)
            if (grid%mass(id) <= grid%small_mass .or. .not. node_owned(grid, id)) cycle
            impulse(1:dim) = merge(-dt*(grid%fint(:, id) + grid%fext(:, id) &
                + grid%mass(id)*gravity(1:dim)), 0.0_wp, grid%held_mask(:, n))
            associate (side => grid%held_face(1, n), axis => grid%held_face(2, n))
                grid%face_impulse(1:dim, side, axis) = grid%face_impulse(1:dim, side, axis) &
                    + impulse(1:dim)
            end associate
            if (grid%keep_reaction) grid%node_reaction(:, id) = grid%node_reaction(:, id) &
                + impulse(1:dim)/dt
        end do
        ! the regions of prescribed_motion: the same, on the components they hold
        if (allocated(grid%region_impulse)) grid%region_impulse = 0.0_wp
        do n = 1, grid%nregion_nodes
            id = grid%region_node(n)
            if (grid%mass(id) <= grid%small_mass .or. .not. node_owned(grid, id)) cycle
            r = grid%region_of(n)
            impulse(1:dim) = merge(-dt*(grid%fint(:, id) + grid%fext(:, id) &
                + grid%mass(id)*gravity(1:dim)), 0.0_wp, grid%region_held(:, r))
            grid%region_impulse(:, r) = grid%region_impulse(:, r) + impulse(1:dim)
            if (grid%keep_reaction) grid%node_reaction(:, id) = grid%node_reaction(:, id) &
                + impulse(1:dim)/dt
            work = work + dot_product(impulse(1:dim), grid%region_velocity(:, r))
        end do
    end subroutine prescribed_impulses

    !> The nodes of the velocity faces move at the face's velocity (their other components
    !> were held at zero by the mask, and their acceleration is zero: the velocity is constant
    !> over the step); those of the regions of prescribed_motion at the region's velocity,
    !> along the components it holds.
    subroutine set_prescribed(grid)
        type(grid_type), intent(inout) :: grid
            !! grid after the masked update

        integer :: n, id

        do n = 1, grid%nprescribed
            id = grid%prescribed_node(n)
            if (grid%mass(id) <= grid%small_mass) cycle
            grid%velocity(:, id) = grid%prescribed_velocity(:, n)
            grid%momentum(:, id) = grid%mass(id)*grid%prescribed_velocity(:, n)
        end do
        do n = 1, grid%nregion_nodes
            id = grid%region_node(n)
            if (grid%mass(id) <= grid%small_mass) cycle
            associate (held => grid%region_held(:, grid%region_of(n)), &
                       v => grid%region_velocity(:, grid%region_of(n)))
                where (held) grid%velocity(:, id) = v
                where (held) grid%momentum(:, id) = grid%mass(id)*v
            end associate
        end do
    end subroutine set_prescribed

    !> The nodes of the faces whose velocity changes in time accelerate from the start velocity
    !> to the end one over the step: (v1 - v0) / dt, which the FLIP update gives the
    !> particles (a shaken base carries the material beside it).
    subroutine accelerate_prescribed(grid, dt)
        type(grid_type), intent(inout) :: grid
            !! grid after set_prescribed
        real(wp), intent(in) :: dt
            !! time step [s]

        integer :: n, id

        do n = 1, grid%nprescribed
            id = grid%prescribed_node(n)
            ! (a node on two velocity faces moves with the later one, prescribed_last)
            if (grid%mass(id) <= grid%small_mass .or. .not. grid%prescribed_last(n)) cycle
            associate (face => grid%prescribed_face(:, n))
                if (.not. grid%face_varies(face(1), face(2))) cycle
            end associate
            grid%acceleration(:, id) = (grid%prescribed_velocity(:, n) &
                - grid%prescribed_start(:, n))/dt
        end do
    end subroutine accelerate_prescribed

    !> Advance the nodal momentum over dt with gravity, damping and boundary conditions.
    !>
    !> f = f_int + m_i g + f_ext (f_ext: extra body forces only). Local damping adds
    !> f_d = - alpha |f| sign(v) per component, f the unbalanced force and v the nodal velocity
    !> at the start of the step. Frictional faces then act on the updated velocities
    !> (apply_contacts). Returns the work of damping and of friction in this step and the
    !> kinetic energy the constraints stop (positive: energy removed), see nnodal_sums. A
    !> fixed component is zero at the start of the step as well as at its end (its force is
    !> dropped too), so it stops the kinetic energy of the mapped start velocity, 1/2 m v^2;
    !> a contact's normal constraint stops the start velocity into the obstacle (beyond
    !> gap / dt) and the velocity the step's forces add, which the particles never move
    !> with (its work, like a fixed component's, is zero at the end velocity). The light
    !> nodes' momentum and forces are folded into their masters before, and their velocities
    !> and accelerations slaved after, by the caller (mpm_halo: fold_light, slave_light).
    subroutine integrate_nodes(grid, dt, gravity, local_damping, alpha, dissipated)
        type(grid_type), intent(inout) :: grid
            !! grid with mass, momentum and forces set
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        logical, intent(in) :: local_damping
            !! apply local damping (case%damping%type == damping_local)
        real(wp), intent(in) :: alpha
            !! local damping coefficient [-]
        real(wp), intent(out) :: dissipated(nnodal_sums)
            !! energy removed in this step by local damping and by contact friction, and
            !! given by the velocity faces (nnodal_sums) [J]

        integer :: i, dim, layer, j, first, last, y, z, lo, hi, a
        real(wp) :: f(3), v0(3), fd(3), acc, held, face_work, restart
        real(wp), allocatable :: partial(:), partial_held(:)

        dim = grid%dim
        call prescribed_impulses(grid, dt, gravity, face_work, restart)
        ! one partial sum per layer of the box (slowest axis), added in layer order: the same
        ! sums with any number of threads
        lo = grid%active_lo(dim)
        hi = grid%active_hi(dim)
        allocate (partial(lo:max(lo, hi)), partial_held(lo:max(lo, hi)))
        partial = 0.0_wp
        partial_held = 0.0_wp
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(grid, dt, gravity, local_damping, alpha, dim, partial, partial_held, lo, hi) &
        !$omp private(layer, j, first, last, y, z, i, f, v0, fd, acc, held, a)
        do layer = lo, hi
            acc = 0.0_wp
            held = 0.0_wp
            do j = box_middle(grid%active_lo, dim), box_middle(grid%active_hi, dim)
                call box_row(grid, grid%active_lo, grid%active_hi, layer, j, first, last, y, z)
                do i = first, last
                    ! an empty node (mass at round-off level) is at rest, so neither the
                    ! forces on it nor a mapped velocity do work the kinetic energy does not see
                    if (grid%mass(i) <= grid%small_mass) then
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
                    if (node_owned(grid, i)) held = held + held_kinetic(grid, i)
                    ! a loop, not a where construct: its mask was a heap temporary per node
                    do a = 1, dim
                        if (grid%constrained(a, i)) then
                            grid%momentum(a, i) = 0.0_wp
                            v0(a) = 0.0_wp
                        end if
                    end do
                    ! (not on the nodes of a rigid body: the body's motion replaces theirs,
                    ! mpm_kernel_rigid)
                    if (local_damping .and. .not. body_node(grid, i)) then
                        fd(1:dim) = -alpha*abs(f(1:dim))*sign(1.0_wp, v0(1:dim))
                        where (v0(1:dim) == 0.0_wp) fd(1:dim) = 0.0_wp
                        where (grid%constrained(:, i)) fd(1:dim) = 0.0_wp
                        f(1:dim) = f(1:dim) + fd(1:dim)
                        ! nodes shared with another image count on one of them
                        if (node_owned(grid, i)) acc = acc &
                            - dt*sum(fd(1:dim)*(v0(1:dim) + 0.5_wp*dt*f(1:dim)/grid%mass(i)))
                    end if
                    where (grid%constrained(:, i)) f(1:dim) = 0.0_wp
                    grid%acceleration(:, i) = f(1:dim)/grid%mass(i)
                    grid%momentum(:, i) = grid%momentum(:, i) + dt*f(1:dim)
                    grid%velocity(:, i) = grid%momentum(:, i)/grid%mass(i)
                end do
            end do
            partial(layer) = acc
            partial_held(layer) = held
        end do
        !$omp end parallel do
        call set_prescribed(grid)
        if (grid%prescribed_varies) call accelerate_prescribed(grid, dt)
        dissipated = 0.0_wp
        dissipated(nodal_faces) = face_work
        do layer = lo, hi
            dissipated(nodal_damping) = dissipated(nodal_damping) + partial(layer)
            dissipated(nodal_boundary) = dissipated(nodal_boundary) + partial_held(layer)
        end do
        ! a velocity face's node is not stopped: held, it goes from its mapped velocity to the
        ! face's start velocity (booked here) and from that to its end velocity (the face's
        ! work); with the whole mapped kinetic energy booked as stopped, a shaken base's APIC
        ! run created 66 % of the base's work
        if (grid%nprescribed > 0) dissipated(nodal_boundary) = dissipated(nodal_boundary) &
            - restart
        if (grid%ncontacts > 0) then
            call apply_contacts(grid, dt, dt, dissipated(nodal_friction), held)
            dissipated(nodal_boundary) = dissipated(nodal_boundary) + held
            do i = 1, grid%ncontacts
                associate (id => grid%contact_node(i))
                    if (grid%mass(id) > grid%small_mass) grid%velocity(:, id) = &
                        grid%momentum(:, id)/grid%mass(id)
                end associate
            end do
        end if
    end subroutine integrate_nodes

    !> Whether node i moves with a rigid body in this step.
    pure logical function body_node(grid, i)
        type(grid_type), intent(in) :: grid
            !! the grid of the step
        integer, intent(in) :: i
            !! node

        body_node = .false.
        if (.not. allocated(grid%region_rigid)) return
        if (grid%region_mark(i) == 0) return
        body_node = grid%region_rigid(grid%region_mark(i)) > 0
    end function body_node

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

end module mpm_kernel_nodal
