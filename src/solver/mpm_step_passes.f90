!> The passes of a step: each scheme as an ordered list of passes (step_passes), which
!> mpm_solver::advance runs in order, and the nodal updates with the light nodes around the
!> nodal kernel (grid_velocity, update_nodes: the folds into the masters before, the slaved
!> values after, traded between images by mpm_halo), and the actions of the boundary
!> conditions that act on their face's nodes (act_on_faces: an absorbing face).
module mpm_step_passes
    use mpm_kinds, only: wp
    use mpm_case, only: scheme_usf, scheme_usl
    use mpm_grid, only: grid_type, node_owned
    use mpm_boundary, only: boundary_holder_type
    use mpm_halo, only: fold_light, slave_light
    use mpm_kernel_nodal, only: nodal_velocity, integrate_nodes, nnodal_sums, nodal_faces
    implicit none
    private
    public :: step_passes, grid_velocity, update_nodes, act_on_faces
    public :: pass_p2g, pass_p2g_mass, pass_start_velocity, pass_p2g_force, pass_nodes, &
        pass_g2p, pass_g2p_stress, pass_g2p_remap, pass_stress, pass_stress_move

    integer, parameter :: pass_p2g = 1, pass_p2g_mass = 2, pass_start_velocity = 3, &
        pass_p2g_force = 4, pass_nodes = 5, pass_g2p = 6, pass_g2p_stress = 7, &
        pass_g2p_remap = 8, pass_stress = 9, pass_stress_move = 10
        !! the passes of a step (step_passes gives each scheme's list): P2G of mass, momentum
        !! and forces; USF's P2G of mass and momentum, its nodal velocities and its P2G of the
        !! internal force; the nodal update; G2P with the moves (and USL's stress update in
        !! the same pass); MUSL's G2P with the remap and the remapped velocities; the stress
        !! update (MUSL's with the moves)
contains

    !> The passes of a step of `scheme`, in order (advance runs them).
    pure function step_passes(scheme, fbar) result(passes)
        integer, intent(in) :: scheme
            !! scheme_usf, scheme_usl or scheme_musl
        logical, intent(in) :: fbar
            !! F-bar: the stress update averages over a cell, after all the particles' gathers
        integer, allocatable :: passes(:)
            !! pass_* codes

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

        ! (again after P2G's fold: it adds nothing more)
        call fold_light(grid, grid%momentum)
        call nodal_velocity(grid, step, friction_work)
        call slave_light(grid, grid%velocity)
    end subroutine grid_velocity

    !> The nodal update (mpm_kernel_nodal::integrate_nodes) with the light nodes: their
    !> momentum and forces to their masters before, their velocities and accelerations
    !> slaved after; in between, the conditions that act on their faces' nodes.
    subroutine update_nodes(grid, faces, dt, gravity, local_damping, alpha, dissipated)
        type(grid_type), intent(inout) :: grid
            !! grid with mass, momentum and forces set
        type(boundary_holder_type), intent(in) :: faces(2, 3)
            !! the condition of each face (case%domain%face; unallocated: free)
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

        real(wp) :: work

        call fold_light(grid, grid%momentum)
        call fold_light(grid, grid%fint)
        call fold_light(grid, grid%fext)
        call integrate_nodes(grid, dt, gravity, local_damping, alpha, dissipated)
        if (grid%nacting > 0) then
            call act_on_faces(grid, faces, dt, work)
            dissipated(nodal_faces) = dissipated(nodal_faces) + work
        end if
        call slave_light(grid, grid%velocity)
        call slave_light(grid, grid%acceleration)
    end subroutine update_nodes

    !> Each face whose condition acts on its nodes (grid%acting_*) applies its `act` to the
    !> nodes of the face that hold material (above grid%small_mass), on copies of their
    !> masses, momenta, velocities and accelerations; the work is summed over this image's
    !> nodes (node_owned). A node on two acting faces (an edge) takes both, in face order.
    subroutine act_on_faces(grid, faces, dt, work)
        type(grid_type), intent(inout) :: grid
            !! grid after the nodal update
        type(boundary_holder_type), intent(in) :: faces(2, 3)
            !! the condition of each face
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(out) :: work
            !! work of the conditions on the nodes in this step [J]

        integer, allocatable :: ids(:)
        logical, allocatable :: owned(:)
        real(wp) :: shared_work, owned_work
        integer :: first, last, side, axis, k

        work = 0.0_wp
        first = 1
        do while (first <= grid%nacting)
            side = grid%acting_face(1, first)
            axis = grid%acting_face(2, first)
            last = first
            do while (last < grid%nacting)
                if (any(grid%acting_face(:, last + 1) /= [side, axis])) exit
                last = last + 1
            end do
            ids = pack(grid%acting_node(first:last), &
                grid%mass(grid%acting_node(first:last)) > grid%small_mass)
            first = last + 1
            owned = [(node_owned(grid, ids(k)), k = 1, size(ids))]
            ! the nodes shared with another image count on the image that owns them
            call act_on(pack(ids, owned), owned_work)
            call act_on(pack(ids, .not. owned), shared_work)
            work = work + owned_work
        end do

    contains

        !> The condition of face (side, axis) on the nodes `at`.
        subroutine act_on(at, face_work)
            integer, intent(in) :: at(:)
                !! the nodes
            real(wp), intent(out) :: face_work
                !! the condition's work on them [J]

            real(wp), allocatable :: momentum(:, :), velocity(:, :), acceleration(:, :)

            face_work = 0.0_wp
            if (size(at) == 0) return
            momentum = grid%momentum(:, at)
            velocity = grid%velocity(:, at)
            acceleration = grid%acceleration(:, at)
            call faces(side, axis)%b%act(axis, grid%dim, dt, grid%dx, grid%mass(at), momentum, &
                velocity, acceleration, face_work)
            grid%momentum(:, at) = momentum
            grid%velocity(:, at) = velocity
            grid%acceleration(:, at) = acceleration
        end subroutine act_on
    end subroutine act_on_faces

end module mpm_step_passes
