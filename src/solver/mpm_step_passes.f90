!> The passes of a step: each scheme as an ordered list of passes (step_passes), which
!> mpm_solver::advance runs in order, and the nodal updates with the light nodes around the
!> nodal kernel (grid_velocity, update_nodes: the folds into the masters before, the slaved
!> values after, traded between images by mpm_halo), and the actions of the boundary
!> conditions that act on their face's nodes (act_on_faces: an absorbing face).
module mpm_step_passes
    use mpm_kinds, only: wp
    use mpm_case, only: scheme_usf, scheme_usl
    use mpm_grid, only: grid_type, node_owned, fold_periodic, slave_periodic
    use mpm_boundary, only: boundary_holder_type
    use mpm_halo, only: fold_light, slave_light, halo_sum
    use mpm_particles, only: particles_type
    use mpm_stencil, only: stencils_type
    use mpm_transfer, only: map_through_particles
    use mpm_kernel_nodal, only: nodal_velocity, integrate_nodes, nnodal_sums, nodal_absorbed, &
        nodal_faces, &
        nodal_rigid, box_middle, box_row
    use mpm_kernel_rigid, only: move_bodies
    implicit none
    private
    public :: step_passes, grid_velocity, update_nodes, act_on_faces, xpic_field, &
        face_velocities
    public :: pass_p2g, pass_p2g_mass, pass_start_velocity, pass_p2g_force, pass_nodes, &
        pass_g2p, pass_g2p_stress, pass_g2p_remap, pass_stress, pass_stress_move, pass_xpic

    integer, parameter :: pass_p2g = 1, pass_p2g_mass = 2, pass_start_velocity = 3, &
        pass_p2g_force = 4, pass_nodes = 5, pass_g2p = 6, pass_g2p_stress = 7, &
        pass_g2p_remap = 8, pass_stress = 9, pass_stress_move = 10, pass_xpic = 11
        !! the passes of a step (step_passes gives each scheme's list): P2G of mass, momentum
        !! and forces; USF's P2G of mass and momentum, its nodal velocities and its P2G of the
        !! internal force; the nodal update; G2P with the moves (and USL's stress update in
        !! the same pass); MUSL's G2P with the remap and the remapped velocities; the stress
        !! update (MUSL's with the moves); with XPIC, after the nodal update, the filtered
        !! start velocities (xpic_field)
contains

    !> The passes of a step of `scheme`, in order (advance runs them).
    pure function step_passes(scheme, fbar, xpic) result(passes)
        integer, intent(in) :: scheme
            !! scheme_usf, scheme_usl or scheme_musl
        logical, intent(in) :: fbar
            !! F-bar: the stress update averages over a cell, after all the particles' gathers
        logical, intent(in), optional :: xpic
            !! XPIC transfer: its filtered start velocities after the nodal update
        integer, allocatable :: passes(:)
            !! pass_* codes

        integer :: k

        select case (scheme)
        case (scheme_usf)
            ! the stress first, with the velocities of the mapped momentum
            passes = [pass_p2g_mass, pass_start_velocity, pass_stress, pass_p2g_force, &
                pass_nodes, pass_g2p]
        case (scheme_usl)
            if (fbar) then
                passes = [pass_p2g, pass_nodes, pass_g2p, pass_stress]
            else
                passes = [pass_p2g, pass_nodes, pass_g2p_stress]
            end if
        case default
            ! MUSL: the stress with the velocities of the remapped momentum
            passes = [pass_p2g, pass_nodes, pass_g2p_remap, pass_stress_move]
        end select
        if (present(xpic)) then
            if (xpic) then
                k = findloc(passes, pass_nodes, dim=1)
                passes = [passes(1:k), pass_xpic, passes(k + 1:)]
            end if
        end if
    end function step_passes

    !> The nodal velocities (mpm_kernel_nodal::nodal_velocity) with the light nodes: their
    !> momentum to their masters before, their velocities slaved after.
    subroutine grid_velocity(grid, step, friction_work)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set
        real(wp), intent(in) :: step
            !! time step the velocities move the particles over [s]
        real(wp), intent(out), optional :: friction_work
            !! work of the friction impulses at these velocities [J]

        real(wp) :: lost

        ! the upper nodes of periodic faces to their lower ones (the MUSL remap scattered
        ! momentum to them again)
        call fold_periodic(grid)
        ! (again after P2G's fold: it adds nothing more)
        call fold_light(grid, grid%momentum)
        call nodal_velocity(grid, step, friction_work)
        ! the rigid bodies' nodes at their bodies' velocities (before the light nodes take
        ! their masters')
        call move_bodies(grid, step, .false., lost)
        call slave_light(grid, grid%velocity)
        call slave_periodic(grid)
    end subroutine grid_velocity

    !> The nodal update (mpm_kernel_nodal::integrate_nodes) with the light nodes: their
    !> momentum and forces to their masters before, their velocities and accelerations
    !> slaved after; in between, the conditions that act on their faces' nodes; then the
    !> rigid bodies (mpm_kernel_rigid::move_bodies).
    subroutine update_nodes(grid, faces, time, dt, gravity, local_damping, alpha, dissipated)
        type(grid_type), intent(inout) :: grid
            !! grid with mass, momentum and forces set
        type(boundary_holder_type), intent(in) :: faces(2, 3)
            !! the condition of each face (case%domain%face; unallocated: free)
        real(wp), intent(in) :: time
            !! time at the start of the step [s]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        logical, intent(in) :: local_damping
            !! apply local damping
        real(wp), intent(in) :: alpha
            !! local damping coefficient [-]
        real(wp), intent(out) :: dissipated(nnodal_sums)
            !! the nodal sums of the step (mpm_kernel_nodal::nnodal_sums) [J]

        real(wp) :: taken, given

        call fold_light(grid, grid%momentum)
        call fold_light(grid, grid%fint)
        call fold_light(grid, grid%fext)
        ! the velocities of the faces whose motion changes in time, at the end of the step
        if (grid%prescribed_varies) call face_velocities(grid, faces, time, time + dt)
        call integrate_nodes(grid, dt, gravity, local_damping, alpha, dissipated)
        if (grid%nacting > 0) then
            ! what leaves through the faces, booked with what the faces stop (boundary_work),
            ! and what an outcrop motion brings in, with the work of the faces (load_work)
            call act_on_faces(grid, faces, time, dt, taken, given)
            dissipated(nodal_absorbed) = taken
            dissipated(nodal_faces) = dissipated(nodal_faces) + given
        end if
        ! each rigid body moves as one (what the lump takes is stopped by a constraint)
        call move_bodies(grid, dt, .true., taken)
        dissipated(nodal_rigid) = taken
        call slave_light(grid, grid%velocity)
        call slave_light(grid, grid%acceleration)
        ! the upper nodes of periodic faces move with their lower ones
        call slave_periodic(grid)
    end subroutine update_nodes

    !> The faces whose prescribed velocity changes in time (grid%face_varies, a seismic base):
    !> each of their (node, face) pairs takes the face's velocity at t0 as the start velocity
    !> of the step and the one at t1 as the velocity it holds.
    subroutine face_velocities(grid, faces, t0, t1)
        type(grid_type), intent(inout) :: grid
            !! the grid
        type(boundary_holder_type), intent(in) :: faces(2, 3)
            !! the condition of each face
        real(wp), intent(in) :: t0
            !! time of the start velocity [s]
        real(wp), intent(in) :: t1
            !! time of the held velocity [s]

        real(wp) :: v0(3, 2, 3), v1(3, 2, 3)
        integer :: n, side, axis

        v0 = 0.0_wp
        v1 = 0.0_wp
        do axis = 1, grid%dim
            do side = 1, 2
                if (.not. grid%face_varies(side, axis)) cycle
                associate (condition => faces(side, axis)%b)
                    v0(:, side, axis) = condition%velocity_at(t0, grid%dim)
                    v1(:, side, axis) = condition%velocity_at(t1, grid%dim)
                end associate
            end do
        end do
        do n = 1, grid%nprescribed
            side = grid%prescribed_face(1, n)
            axis = grid%prescribed_face(2, n)
            if (.not. grid%face_varies(side, axis)) cycle
            grid%prescribed_start(:, n) = v0(1:grid%dim, side, axis)
            grid%prescribed_velocity(:, n) = v1(1:grid%dim, side, axis)
        end do
    end subroutine face_velocities

    !> Each face whose condition acts on its nodes (grid%acting_*) applies its `act` to the
    !> nodes of the face that hold material (above grid%small_mass), on copies of their
    !> masses, momenta, velocities, accelerations and held components; the energy they take
    !> is summed over this image's nodes (node_owned). A node on two acting faces (an edge)
    !> takes both, in face order.
    subroutine act_on_faces(grid, faces, time, dt, taken, given)
        type(grid_type), intent(inout) :: grid
            !! grid after the nodal update
        type(boundary_holder_type), intent(in) :: faces(2, 3)
            !! the condition of each face
        real(wp), intent(in) :: time
            !! time at the start of the step [s]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(out) :: taken
            !! energy the conditions took from the nodes in this step [J]
        real(wp), intent(out) :: given
            !! work of the motions they impose from outside on the nodes in this step [J]

        integer, allocatable :: ids(:)
        logical, allocatable :: owned(:)
        real(wp) :: shared_work, owned_work, shared_given, owned_given
        integer :: first, last, side, axis, k

        taken = 0.0_wp
        given = 0.0_wp
        first = 1
        do while (first <= grid%nacting)
            side = grid%acting_face(1, first)
            axis = grid%acting_face(2, first)
            last = first
            do while (last < grid%nacting)
                if (any(grid%acting_face(:, last + 1) /= [side, axis])) exit
                last = last + 1
            end do
            ! the pairs (positions in the acting list) whose nodes hold material
            ids = pack([(k, k = first, last)], &
                grid%mass(grid%acting_node(first:last)) > grid%small_mass)
            first = last + 1
            owned = [(node_owned(grid, grid%acting_node(ids(k))), k = 1, size(ids))]
            ! the nodes shared with another image count on the image that owns them
            call act_on(pack(ids, owned), owned_work, owned_given)
            call act_on(pack(ids, .not. owned), shared_work, shared_given)
            taken = taken + owned_work
            given = given + owned_given
        end do

    contains

        !> The condition of face (side, axis) on the nodes of the acting pairs `pairs`.
        subroutine act_on(pairs, face_work, face_given)
            integer, intent(in) :: pairs(:)
                !! positions in the acting list
            real(wp), intent(out) :: face_work
                !! the energy the condition took from them [J]
            real(wp), intent(out) :: face_given
                !! the work of the motion it imposes on them [J]

            real(wp), allocatable :: momentum(:, :), velocity(:, :), acceleration(:, :), &
                displacement(:, :)
            integer, allocatable :: at(:)

            face_work = 0.0_wp
            face_given = 0.0_wp
            if (size(pairs) == 0) return
            at = grid%acting_node(pairs)
            momentum = grid%momentum(:, at)
            velocity = grid%velocity(:, at)
            acceleration = grid%acceleration(:, at)
            displacement = grid%acting_disp(:, pairs)
            call faces(side, axis)%b%act(axis, grid%dim, time, dt, grid%dx, grid%mass(at), &
                grid%acting_area(pairs), grid%constrained(:, at), momentum, velocity, &
                acceleration, displacement, face_work, face_given)
            grid%momentum(:, at) = momentum
            grid%velocity(:, at) = velocity
            grid%acceleration(:, at) = acceleration
            grid%acting_disp(:, pairs) = displacement
        end subroutine act_on
    end subroutine act_on_faces

    !> XPIC(m) (Hammerquist and Nairn 2017, "A new method for material point method particle
    !> updates that reduces noise and enhances stability"): the start velocity that G2P gives
    !> the particles, with the step's accelerations, sum N_ip (xpic_i + dt a_i), in
    !> grid%xpic.
    !>
    !> FLIP keeps v_p of the start of the step, and with it the velocities the grid does not
    !> see (the null space of the particle-to-grid map: particles beside each other moving
    !> opposite ways); PIC replaces v_p by S v_g (v_g the nodal velocity of the start, S the
    !> interpolation to the particles), which removes them and damps every mode the grid
    !> resolves but poorly. XPIC(m) replaces v_p by [I - (I - A)^m] v_p, A = S M^-1 S^T M_p
    !> the map particles -> grid -> particles: m = 1 is PIC, and as m grows only the null
    !> space is taken out. On the grid: xpic = sum_k=1..m (-1)^(k+1) C(m, k) A_g^(k-1) v_g,
    !> A_g u = M^-1 sum_p m_p N_ip (S u)_p (one gather and one scatter per power), each power
    !> with the held components of v_g (v_g = v - dt a after the nodal update: zero at a
    !> fixed component, the face's velocity at a velocity face, so that the sum, whose
    !> coefficients add up to 1, keeps them) and slaved at the light nodes. The momentum is
    !> kept: the passes borrow grid%momentum.
    subroutine xpic_field(grid, particles, stc, dt, order, layers)
        type(grid_type), intent(inout) :: grid
            !! grid after the nodal update
        type(particles_type), intent(in) :: particles
            !! particles of the step
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        real(wp), intent(in) :: dt
            !! time step [s]
        integer, intent(in) :: order
            !! m >= 1
        integer, intent(in) :: layers
            !! node layers shared at a cut (shape_type%halo_width)

        real(wp), allocatable :: kept(:, :), u(:, :), start(:, :)
        real(wp) :: coefficient
        integer :: k, i, q
        integer, allocatable :: ids(:)

        if (.not. allocated(grid%xpic)) then
            allocate (grid%xpic(grid%dim, grid%nnodes))
        else if (size(grid%xpic, 2) /= grid%nnodes) then
            deallocate (grid%xpic)
            allocate (grid%xpic(grid%dim, grid%nnodes))
        end if
        ! nodal work only in the box of the step's P2G: every other node is empty (zero
        ! velocity, acceleration and momentum), and the gathers read only the nodes of the
        ! particles' stencils
        ids = box_nodes(grid)
        allocate (start(grid%dim, size(ids)))
        ! the nodal velocity of the start of the step, as the nodal update formed it: zero on
        ! the empty nodes and in the fixed components, the face's at a velocity face, slaved
        ! at the light nodes
        coefficient = real(order, wp)
        do q = 1, size(ids)
            i = ids(q)
            start(:, q) = grid%velocity(:, i) - dt*grid%acceleration(:, i)
            grid%xpic(:, i) = coefficient*start(:, q)
        end do
        if (order == 1) return
        ! start and kept by box entry; u by node, for the gathers
        allocate (kept(grid%dim, size(ids)), u(grid%dim, grid%nnodes))
        do q = 1, size(ids)
            i = ids(q)
            kept(:, q) = grid%momentum(:, i)
            u(:, i) = start(:, q)
        end do
        do k = 2, order
            call map_through_particles(grid, particles, stc, u)
            call halo_sum(grid, layers, momentum=.true.)
            call fold_light(grid, grid%momentum)
            do q = 1, size(ids)
                i = ids(q)
                if (grid%mass(i) > grid%small_mass) then
                    u(:, i) = grid%momentum(:, i)/grid%mass(i)
                else
                    u(:, i) = 0.0_wp
                end if
            end do
            ! the light nodes (no mass of their own) from their masters, the held components
            ! at their values; then sum_k (-1)^(k+1) C(m, k) u_k, the binomial coefficient
            ! from C(m, k) = C(m, k - 1) (m - k + 1) / k
            call slave_light(grid, u)
            coefficient = -coefficient*real(order - k + 1, wp)/real(k, wp)
            do q = 1, size(ids)
                i = ids(q)
                where (grid%constrained(:, i)) u(:, i) = start(:, q)
                grid%xpic(:, i) = grid%xpic(:, i) + coefficient*u(:, i)
            end do
        end do
        do q = 1, size(ids)
            i = ids(q)
            grid%momentum(:, i) = kept(:, q)
        end do
    end subroutine xpic_field

    !> Node indices (1-based) of the box of the step's P2G (grid%active_lo .. active_hi).
    function box_nodes(grid) result(ids)
        type(grid_type), intent(in) :: grid
            !! grid after a P2G
        integer, allocatable :: ids(:)

        integer :: lo(3), hi(3), layer, j, first, last, y, z, n, dim, id

        dim = grid%dim
        lo = max(0, grid%active_lo)
        hi = min(grid%nn - 1, grid%active_hi)
        if (any(hi(1:dim) < lo(1:dim))) then
            allocate (ids(0))
            return
        end if
        allocate (ids(product(hi(1:dim) - lo(1:dim) + 1)))
        n = 0
        do layer = lo(dim), hi(dim)
            do j = box_middle(lo, dim), box_middle(hi, dim)
                call box_row(grid, lo, hi, layer, j, first, last, y, z)
                do id = first, last
                    n = n + 1
                    ids(n) = id
                end do
            end do
        end do
    end function box_nodes

end module mpm_step_passes
