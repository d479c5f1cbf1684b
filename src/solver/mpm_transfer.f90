!> The particle passes of one explicit step: the threaded loops over particles that call the
!> kernels (src/solver/kernels/).
!>
!> Particle-to-grid (P2G) scatters mass, momentum and forces to the nodes (mpm_kernel_scatter;
!> the pass is in mpm_transfer_p2g, passed on by this module); grid-to-particle (G2P) gathers
!> accelerations and velocities back (mpm_kernel_gather); the stress update uses the nodal
!> velocities chosen by the scheme (its kernel for a block of particles: mpm_kernel_stress).
!> The nodal update is mpm_kernel_nodal. Each pass is one procedure; the step (mpm_solver::advance)
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
    use mpm_stencil, only: stencils_type, particle_weights
    use mpm_shape, only: max_stencil_nodes, shape_type
    use mpm_material, only: material_holder_type
    use mpm_kernel_stress, only: stress_block, determinant, gather_block, nstress_sums
    use mpm_kernel_scatter, only: scatter_particle
    use mpm_kernel_gather, only: gather_particle
    use mpm_transfer_p2g, only: p2g, p2g_options_type, map_through_particles, &
        next_scatter_type, open_next_scatter, next_scatter, close_next_scatter, &
        scatter_buffer, fold, group_count, group_range
    implicit none
    private
    public :: p2g, p2g_options_type, g2p, motion_type, report_lost, update_stress, nstress_sums
    public :: map_through_particles

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

contains

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
