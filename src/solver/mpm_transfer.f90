!> The particle and grid passes of one explicit step.
!>
!> Particle-to-grid (P2G) scatters mass, momentum and forces to the nodes; the nodal update
!> integrates the momentum with damping and boundary conditions; grid-to-particle (G2P)
!> gathers accelerations and velocities back; the stress update uses the nodal velocities
!> chosen by the scheme. Each pass is one procedure; the scheme (USF/USL/MUSL) only orders
!> them (see mpm_solver).
module mpm_transfer
    use mpm_kinds, only: wp
    use mpm_strings, only: vector_text
    use mpm_error, only: error_type, fatal_error, exit_numerical
    use mpm_grid, only: grid_type, contact_index, node_position
    use mpm_particles, only: particles_type
    use mpm_shape, only: shape_type, stencil_type
    use mpm_material, only: material_holder_type
    use mpm_stress, only: double_contraction
    use mpm_case, only: damping_local, bc_free
    implicit none
    private
    public :: reset_grid, p2g, nodal_velocity, integrate_nodes, g2p, move_particles, remap_momentum
    public :: update_stress

    real(wp), parameter :: contact_tolerance = 1.0e-3_wp
        !! material closer to a frictional face than this fraction of dx touches it [-]
    real(wp), parameter :: load_smoothing = 0.1_wp
        !! weight of the newest step in the running mean of the normal contact impulse when
        !! grid%contact_time is 0 [-]

contains

    !> Zero the nodal fields before a P2G pass.
    subroutine reset_grid(grid)
        type(grid_type), intent(inout) :: grid
            !! the grid

        grid%mass = 0.0_wp
        grid%momentum = 0.0_wp
        grid%fint = 0.0_wp
        grid%fext = 0.0_wp
        if (grid%ncontacts > 0) grid%contact_gap = huge(1.0_wp)
    end subroutine reset_grid

    !> Scatter particle mass, momentum and gravity (and the internal force when asked).
    !>
    !> f_int,i = - sum_p V_p sigma_p . grad N_i(x_p); in 2D only the in-plane components.
    subroutine p2g(grid, particles, shape, gravity, with_mass, with_fint, fbar)
        type(grid_type), intent(inout) :: grid
            !! grid receiving the nodal sums
        type(particles_type), intent(in) :: particles
            !! particles
        class(shape_type), intent(in) :: shape
            !! shape function
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        logical, intent(in) :: with_mass
            !! scatter mass, momentum and external force
        logical, intent(in) :: with_fint
            !! scatter the internal force
        logical, intent(in) :: fbar
            !! F-bar: the internal force takes the pressure of each particle as the mean of its
            !! cell, the counterpart of the cell-averaged volume change of `update_stress`

        integer :: p, c, id, dim
        type(stencil_type) :: st
        real(wp) :: w, mw, f(3), s(6)
        real(wp), allocatable :: cell_pv(:), cell_v(:)

        dim = grid%dim
        if (with_fint .and. fbar) then
            ! the stress power sum_p V_p p_p (mean of dJ over the cell) equals
            ! sum_q V_q (mean of V p over the cell) tr(L_q): the force that does the work of
            ! the averaged strains uses the averaged pressure
            allocate (cell_pv(product(grid%ncells)), cell_v(product(grid%ncells)))
            cell_pv = 0.0_wp
            cell_v = 0.0_wp
            do p = 1, particles%n
                c = cell_of(grid, particles%x(:, p))
                cell_pv(c) = cell_pv(c) + particles%volume(p)*sum(particles%stress(1:3, p))/3.0_wp
                cell_v(c) = cell_v(c) + particles%volume(p)
            end do
            where (cell_v > 0.0_wp) cell_pv = cell_pv/cell_v
        end if
        do p = 1, particles%n
            call shape%evaluate(grid, particles%x(:, p), particles%lp(:, p), st)
            do c = 1, st%count
                id = st%node(c)
                w = st%w(c)
                if (with_mass) then
                    mw = particles%mass(p)*w
                    grid%mass(id) = grid%mass(id) + mw
                    grid%momentum(:, id) = grid%momentum(:, id) + mw*particle_velocity(grid, &
                        particles, p, id)
                    grid%fext(:, id) = grid%fext(:, id) + mw*gravity(1:dim)
                    if (allocated(particles%body_force)) grid%fext(:, id) = grid%fext(:, id) &
                        + mw*particles%body_force(:, p)
                end if
                if (with_fint .and. fbar) then
                    s(1:particles%nstress) = particles%stress(:, p)
                    s(1:3) = s(1:3) + cell_pv(cell_of(grid, particles%x(:, p))) - sum(s(1:3))/3.0_wp
                    call internal_force(s(1:particles%nstress), st%dw(:, c), dim, f)
                    grid%fint(:, id) = grid%fint(:, id) - particles%volume(p)*f(1:dim)
                else if (with_fint) then
                    call internal_force(particles%stress(:, p), st%dw(:, c), dim, f)
                    grid%fint(:, id) = grid%fint(:, id) - particles%volume(p)*f(1:dim)
                end if
            end do
            if (with_mass .and. grid%ncontacts > 0) call contact_gaps(grid, particles, p, st)
        end do
    end subroutine p2g

    !> Record, for the frictional-face nodes a particle maps to, the gap between the
    !> particle's domain and the face (negative when it reaches past it).
    subroutine contact_gaps(grid, particles, p, st)
        type(grid_type), intent(inout) :: grid
        type(particles_type), intent(in) :: particles
        integer, intent(in) :: p
        type(stencil_type), intent(in) :: st

        integer :: a, side, c, k
        real(wp) :: gap, face

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
                do k = 1, st%count
                    c = contact_index(grid, st%node(k), side, a)
                    if (c > 0) grid%contact_gap(c) = min(grid%contact_gap(c), gap)
                end do
            end do
        end do
    end subroutine contact_gaps

    !> sigma . grad N for Voigt-stored stress.
    pure subroutine internal_force(s, dw, dim, f)
        real(wp), intent(in) :: s(:)
        real(wp), intent(in) :: dw(3)
        integer, intent(in) :: dim
        real(wp), intent(out) :: f(3)

        if (dim == 2) then
            f(1) = s(1)*dw(1) + s(4)*dw(2)
            f(2) = s(4)*dw(1) + s(2)*dw(2)
            f(3) = 0.0_wp
        else
            f(1) = s(1)*dw(1) + s(4)*dw(2) + s(6)*dw(3)
            f(2) = s(4)*dw(1) + s(2)*dw(2) + s(5)*dw(3)
            f(3) = s(6)*dw(1) + s(5)*dw(2) + s(3)*dw(3)
        end if
    end subroutine internal_force

    !> Nodal velocity v_i = p_i / m_i with the boundary conditions applied.
    subroutine nodal_velocity(grid)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set

        integer :: i
        real(wp) :: work

        call apply_contacts(grid, 0.0_wp, work)
        do i = 1, grid%nnodes
            if (grid%mass(i) > 0.0_wp) then
                where (grid%constrained(:, i)) grid%momentum(:, i) = 0.0_wp
                grid%velocity(:, i) = grid%momentum(:, i)/grid%mass(i)
            else
                grid%velocity(:, i) = 0.0_wp
            end if
        end do
    end subroutine nodal_velocity

    !> Advance the nodal momentum over dt with damping and boundary conditions.
    !>
    !> Local damping adds f_d = - alpha |f| sign(v) per component, f = f_int + f_ext the
    !> unbalanced force and v the nodal velocity at the start of the step. Frictional faces
    !> then act on the updated velocities (apply_contacts). Returns the energy damping and
    !> boundary friction removed in this step (positive).
    subroutine integrate_nodes(grid, dt, damping, alpha, dissipated)
        type(grid_type), intent(inout) :: grid
            !! grid with mass, momentum and forces set
        real(wp), intent(in) :: dt
            !! time step [s]
        integer, intent(in) :: damping
            !! case%damping
        real(wp), intent(in) :: alpha
            !! local damping coefficient [-]
        real(wp), intent(out) :: dissipated
            !! energy removed by local damping and boundary friction in this step [J]

        integer :: i
        real(wp) :: f(3), v0(3), fd(3), contact_work
        integer :: dim

        dim = grid%dim
        dissipated = 0.0_wp
        do i = 1, grid%nnodes
            if (grid%mass(i) <= 0.0_wp) then
                grid%momentum(:, i) = 0.0_wp
                grid%acceleration(:, i) = 0.0_wp
                cycle
            end if
            f(1:dim) = grid%fint(:, i) + grid%fext(:, i)
            v0(1:dim) = grid%momentum(:, i)/grid%mass(i)
            ! Held components are zero in the nodal velocity of the start of the step as well as
            ! of its end, so their acceleration is zero and the FLIP update leaves the particle
            ! velocities beside a fixed or sliding face to the forces (as Uintah does). Putting
            ! the removed mapped velocity into the acceleration instead makes the manufactured
            ! solution less accurate (cpGIMP MUSL, 64 cells: 9.4e-5 m against 3.5e-5 m).
            where (grid%constrained(:, i))
                grid%momentum(:, i) = 0.0_wp
                v0(1:dim) = 0.0_wp
            end where
            if (damping == damping_local) then
                fd(1:dim) = -alpha*abs(f(1:dim))*sign(1.0_wp, v0(1:dim))
                where (v0(1:dim) == 0.0_wp) fd(1:dim) = 0.0_wp
                where (grid%constrained(:, i)) fd(1:dim) = 0.0_wp
                f(1:dim) = f(1:dim) + fd(1:dim)
                dissipated = dissipated - dt*sum(fd(1:dim)*(v0(1:dim) &
                    + 0.5_wp*dt*f(1:dim)/grid%mass(i)))
            end if
            where (grid%constrained(:, i)) f(1:dim) = 0.0_wp
            if (grid%mass(i) < grid%small_mass) f(1:dim) = 0.0_wp
            grid%acceleration(:, i) = f(1:dim)/grid%mass(i)
            grid%momentum(:, i) = grid%momentum(:, i) + dt*f(1:dim)
        end do
        call apply_contacts(grid, dt, contact_work)
        dissipated = dissipated + contact_work
        do i = 1, grid%nnodes
            if (grid%mass(i) > 0.0_wp) then
                grid%velocity(:, i) = grid%momentum(:, i)/grid%mass(i)
            else
                grid%velocity(:, i) = 0.0_wp
            end if
        end do
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
            !! kinetic energy the contacts removed (normal impact and friction) [J]

        integer :: c, id, a, dim
        real(wp) :: v(3), vnew(3), vn, vt_norm, factor, weight
        logical :: touching

        dim = grid%dim
        work = 0.0_wp
        do c = 1, grid%ncontacts
            id = grid%contact_node(c)
            if (grid%mass(id) <= 0.0_wp) then
                if (dt > 0.0_wp) grid%contact_load(c) = 0.0_wp
                cycle
            end if
            a = grid%contact_axis(c)
            v(1:dim) = grid%momentum(:, id)/grid%mass(id)
            vn = v(a)*grid%contact_normal(c)
            touching = grid%contact_gap(c) <= contact_tolerance*grid%dx
            if (.not. touching) vn = 0.0_wp
            vnew(1:dim) = v(1:dim)
            if (vn > 0.0_wp) vnew(a) = 0.0_wp
            if (dt > 0.0_wp) then
                ! running mean over a fixed time, so that the friction does not depend on dt
                weight = load_smoothing
                if (grid%contact_time > 0.0_wp) weight = min(1.0_wp, dt/grid%contact_time)
                grid%contact_load(c) = (1.0_wp - weight)*grid%contact_load(c) &
                    + weight*max(vn, 0.0_wp)*grid%mass(id)
                vt_norm = norm2(vnew(1:dim) - vnew(a)*unit(a, dim))
                if (vt_norm > 0.0_wp) then
                    factor = max(0.0_wp, &
                        1.0_wp - grid%contact_mu(c)*grid%contact_load(c)/(grid%mass(id)*vt_norm))
                    vnew(1:dim) = factor*(vnew(1:dim) - vnew(a)*unit(a, dim)) &
                        + vnew(a)*unit(a, dim)
                end if
                grid%acceleration(:, id) = grid%acceleration(:, id) + (vnew(1:dim) - v(1:dim))/dt
            end if
            grid%momentum(:, id) = grid%mass(id)*vnew(1:dim)
            work = work + 0.5_wp*grid%mass(id)*(sum(v(1:dim)**2) - sum(vnew(1:dim)**2))
        end do
    end subroutine apply_contacts

    !> Gather nodal accelerations and velocities: v_p += dt sum N_i a_i (FLIP), and the
    !> position increment dx_p = dt sum N_i v_i, applied later by move_particles so that every
    !> pass of a step uses the shape functions at the start-of-step positions.
    subroutine g2p(grid, particles, shape, dt, flip, dxp)
        type(grid_type), intent(in) :: grid
            !! grid after the nodal update
        type(particles_type), intent(inout) :: particles
            !! particles whose velocities are updated
        class(shape_type), intent(in) :: shape
            !! shape function
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: flip
            !! FLIP fraction of the velocity update (1: FLIP, 0: PIC) [-]
        real(wp), intent(out) :: dxp(:, :)
            !! position increment of each particle (dim, n) [m]

        integer :: p, c, k, dim
        type(stencil_type) :: st
        real(wp) :: a(3), v(3)

        dim = grid%dim
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(grid, particles, shape, dt, flip, dim, dxp) private(p, c, k, st, a, v)
        do p = 1, particles%n
            call shape%evaluate(grid, particles%x(:, p), particles%lp(:, p), st)
            a = 0.0_wp
            v = 0.0_wp
            do c = 1, st%count
                a(1:dim) = a(1:dim) + st%w(c)*grid%acceleration(:, st%node(c))
                v(1:dim) = v(1:dim) + st%w(c)*grid%velocity(:, st%node(c))
            end do
            if (allocated(particles%affine)) then
                ! APIC: the particle takes the nodal velocity field, its value and its gradient.
                ! A particle alone on its nodes would only get back the affine field it gave
                ! them, and a stretching one would keep stretching without end (its volume grew
                ! by 1e72 at the front of a collapse); alone, it moves without an affine part.
                particles%v(:, p) = v(1:dim)
                particles%affine(:, :, p) = 0.0_wp
                if (.not. alone(grid, particles%mass(p), st)) then
                    do c = 1, st%count
                        do k = 1, dim
                            particles%affine(:, k, p) = particles%affine(:, k, p) &
                                + grid%velocity(:, st%node(c))*st%dw(k, c)
                        end do
                    end do
                end if
            else if (flip < 1.0_wp) then
                particles%v(:, p) = flip*(particles%v(:, p) + dt*a(1:dim)) &
                    + (1.0_wp - flip)*v(1:dim)
            else
                particles%v(:, p) = particles%v(:, p) + dt*a(1:dim)
            end if
            dxp(:, p) = dt*v(1:dim)
        end do
        !$omp end parallel do
    end subroutine g2p

    !> Apply the position increments of the step; fails (exit_numerical) when a particle
    !> leaves the grid through a free face or its position is not finite.
    subroutine move_particles(grid, particles, dxp, error)
        type(grid_type), intent(in) :: grid
            !! grid (its extent)
        type(particles_type), intent(inout) :: particles
            !! particles to move
        real(wp), intent(in) :: dxp(:, :)
            !! position increments (dim, n) [m]
        type(error_type), allocatable, intent(out) :: error
            !! set when a particle leaves the grid

        integer :: p, dim, bad, a
        real(wp) :: lo(3), hi(3), x(3)
        logical :: closed_lo(3), closed_hi(3)

        dim = grid%dim
        closed_lo = .false.
        closed_hi = .false.
        lo = grid%origin
        hi = grid%origin + grid%dx*real(grid%nn - 1, wp)
        bad = 0
        closed_lo(1:dim) = grid%bc(1, 1:dim) /= bc_free
        closed_hi(1:dim) = grid%bc(2, 1:dim) /= bc_free
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(particles, dxp, dim, lo, hi, closed_lo, closed_hi) private(p, x, a) &
        !$omp reduction(max: bad)
        do p = 1, particles%n
            x(1:dim) = particles%x(:, p) + dxp(:, p)
            ! a closed face (sliding, fixed, frictional) cannot be crossed: the nodal velocity
            ! keeps material off it, but a point carried by the velocities of the nodes
            ! beside the face can overshoot it by a fraction of a step; it stays on the face
            do a = 1, dim
                if (closed_lo(a) .and. x(a) < lo(a)) x(a) = lo(a)
                if (closed_hi(a) .and. x(a) > hi(a)) x(a) = hi(a)
            end do
            particles%u(:, p) = particles%u(:, p) + (x(1:dim) - particles%x(:, p))
            particles%x(:, p) = x(1:dim)
            if (.not. (all(particles%x(:, p) >= lo(1:dim)) .and. &
                       all(particles%x(:, p) <= hi(1:dim)))) then
                bad = max(bad, p)
            end if
        end do
        !$omp end parallel do
        if (bad > 0) call report_lost(particles, bad, lo, hi, error)
    end subroutine move_particles

    subroutine report_lost(particles, p, lo, hi, error)
        type(particles_type), intent(in) :: particles
        integer, intent(in) :: p
        real(wp), intent(in) :: lo(3), hi(3)
        type(error_type), allocatable, intent(out) :: error

        character(len=600) :: msg
        integer :: dim

        dim = particles%dim
        write (msg, "(a,i0,a,a,a,a,a,a,a)") "particle ", p, " left the grid: position (", &
            vector_text(particles%x(:, p)), ") m, grid from (", vector_text(lo(1:dim)), &
            ") to (", vector_text(hi(1:dim)), &
            ") m; enlarge the domain or close its faces with boundary conditions"
        call fatal_error(error, trim(msg), exit_numerical)
    end subroutine report_lost

    !> MUSL: map the updated particle momentum back to the nodes and recompute v_i.
    subroutine remap_momentum(grid, particles, shape)
        type(grid_type), intent(inout) :: grid
            !! grid whose mass is set
        type(particles_type), intent(in) :: particles
            !! particles with updated velocities
        class(shape_type), intent(in) :: shape
            !! shape function

        integer :: p, c, id
        type(stencil_type) :: st

        grid%momentum = 0.0_wp
        do p = 1, particles%n
            call shape%evaluate(grid, particles%x(:, p), particles%lp(:, p), st)
            do c = 1, st%count
                id = st%node(c)
                grid%momentum(:, id) = grid%momentum(:, id) &
                    + st%w(c)*particles%mass(p)*particle_velocity(grid, particles, p, id)
            end do
        end do
        call nodal_velocity(grid)
    end subroutine remap_momentum

    !> Stress update from the nodal velocities in grid%velocity.
    !>
    !> L = sum_i v_i (x) grad N_i; strain increment D dt, spin W dt; F <- (I + L dt) F;
    !> V = det(F) V0; GIMP half-sizes lp = lp0 F_aa (contiguous particle GIMP). Returns the
    !> work of the stresses over the step (strain energy increment). Like every pass of a
    !> step, it evaluates the shape functions at the start-of-step positions.
    !>
    !> With `fbar`, the volumetric part of each increment is replaced by the mean of the cell
    !> the particle is in (F-bar: dF_bar = (dJ_cell / dJ_p)^(1/dim) dF_p, with dJ_cell the
    !> volume-weighted mean of dJ over the particles of the cell). Nearly isochoric plastic
    !> flow (Mohr-Coulomb with psi = 0) otherwise locks on the low-order shape functions and
    !> leaves a checkerboard of pressures, and with it of strengths, between the particles of
    !> a cell (Coombs et al. 2018; Wyser et al. 2021 average the pressure per cell).
    subroutine update_stress(grid, particles, shape, materials, dt, fbar, strain_work, dxp)
        type(grid_type), intent(in) :: grid
            !! grid with nodal velocities
        type(particles_type), intent(inout) :: particles
            !! particles to update
        class(shape_type), intent(in) :: shape
            !! shape function
        type(material_holder_type), intent(in) :: materials(:)
            !! materials of the case
        real(wp), intent(in) :: dt
            !! time step [s]
        logical, intent(in) :: fbar
            !! average the volume change of the step per cell
        real(wp), intent(out) :: strain_work
            !! sum_p (V sigma)_mid : d_eps [J] (per metre in 2D)
        real(wp), intent(inout), optional :: dxp(:, :)
            !! when present, the position increment dt sum_i N_i v_i from the same nodal
            !! velocities as the strain (MUSL) [m]

        integer :: p, dim, ns, a
        real(wp) :: gradv(3, 3), ldt(3, 3), de(6), omega(3), sold(6), dF(3, 3), jac, scale, v(3), &
            vold
        real(wp), allocatable :: grads(:, :, :), cell_old(:), cell_new(:)
        integer, allocatable :: cell(:)

        dim = grid%dim
        ns = particles%nstress
        strain_work = 0.0_wp
        if (fbar) then
            allocate (grads(3, 3, particles%n), cell(particles%n))
            allocate (cell_old(product(grid%ncells)), cell_new(product(grid%ncells)))
            !$omp parallel do default(none) schedule(static) &
            !$omp shared(grid, particles, shape, dim, dt, grads, cell, dxp) private(p, v)
            do p = 1, particles%n
                if (present(dxp)) then
                    call velocity_gradient(grid, shape, particles%x(:, p), particles%lp(:, p), &
                        grads(:, :, p), v(1:dim))
                    dxp(:, p) = dt*v(1:dim)
                else
                    call velocity_gradient(grid, shape, particles%x(:, p), particles%lp(:, p), &
                        grads(:, :, p))
                end if
                cell(p) = cell_of(grid, particles%x(:, p))
            end do
            !$omp end parallel do
            cell_old = 0.0_wp
            cell_new = 0.0_wp
            do p = 1, particles%n   ! serial: a fixed order of the sums
                dF = increment(grads(:, :, p), dt, dim)
                cell_old(cell(p)) = cell_old(cell(p)) + particles%volume(p)
                cell_new(cell(p)) = cell_new(cell(p)) &
                    + particles%volume(p)*determinant(dF, dim)
            end do
        end if
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(grid, particles, shape, materials, dt, dim, ns, fbar, grads, cell, &
        !$omp cell_old, cell_new, dxp) &
        !$omp private(p, gradv, v, ldt, de, omega, sold, vold, dF, jac, a, scale) &
        !$omp reduction(+: strain_work)
        do p = 1, particles%n
            if (fbar) then
                gradv = grads(:, :, p)   ! and dxp, when asked, from the same pass
            else if (present(dxp)) then
                call velocity_gradient(grid, shape, particles%x(:, p), particles%lp(:, p), &
                    gradv, v(1:dim))
                dxp(:, p) = dt*v(1:dim)
            else
                call velocity_gradient(grid, shape, particles%x(:, p), particles%lp(:, p), gradv)
            end if
            ! gradv(i, j) = d v_i / d x_j; ldt = dt gradv, dF = I + ldt
            ldt = dt*gradv
            if (fbar) then
                dF = increment(gradv, dt, dim)
                jac = determinant(dF, dim)
                if (jac > 0.0_wp .and. cell_new(cell(p)) > 0.0_wp) then
                    scale = (cell_new(cell(p))/(cell_old(cell(p))*jac))**(1.0_wp/dim)
                    ldt(1:dim, 1:dim) = scale*dF(1:dim, 1:dim)
                    do a = 1, dim
                        ldt(a, a) = ldt(a, a) - 1.0_wp
                    end do
                end if
            end if
            de = 0.0_wp
            omega = 0.0_wp
            de(1) = ldt(1, 1)
            de(2) = ldt(2, 2)
            de(4) = 0.5_wp*(ldt(1, 2) + ldt(2, 1))
            omega(1) = 0.5_wp*(ldt(1, 2) - ldt(2, 1))
            if (dim == 3) then
                de(3) = ldt(3, 3)
                de(5) = 0.5_wp*(ldt(2, 3) + ldt(3, 2))
                de(6) = 0.5_wp*(ldt(3, 1) + ldt(1, 3))
                omega(2) = 0.5_wp*(ldt(2, 3) - ldt(3, 2))
                omega(3) = 0.5_wp*(ldt(3, 1) - ldt(1, 3))
            end if
            sold(1:ns) = particles%stress(:, p)
            vold = particles%volume(p)
            call materials(particles%material(p))%m%update_stress(particles%stress(:, p), &
                de(1:ns), omega, dt, particles%state(:, p))
            particles%strain(:, p) = particles%strain(:, p) + de(1:ns)
            ! deformation gradient, volume and particle domain
            dF = 0.0_wp
            do a = 1, dim
                dF(a, a) = 1.0_wp
            end do
            dF(1:dim, 1:dim) = dF(1:dim, 1:dim) + ldt(1:dim, 1:dim)
            particles%f(:, :, p) = matmul(dF(1:dim, 1:dim), particles%f(:, :, p))
            jac = determinant(particles%f(:, :, p), dim)
            particles%volume(p) = jac*particles%volume0(p)
            do a = 1, dim
                particles%lp(a, p) = particles%lp0(a, p)*abs(particles%f(a, a, p))
            end do
            ! trapezoidal rule on V sigma (volume and stress at both ends of the step): second
            ! order in dt, also when the volume changes with the strain (large deformation)
            strain_work = strain_work + 0.5_wp*double_contraction(vold*sold(1:ns) &
                + particles%volume(p)*particles%stress(:, p), de(1:ns))
        end do
        !$omp end parallel do
    end subroutine update_stress

    !> Velocity gradient L(i, j) = d v_i / d x_j at a particle from the nodal velocities, and
    !> optionally the velocity sum_i N_i v_i itself.
    subroutine velocity_gradient(grid, shape, x, lp, gradv, v)
        type(grid_type), intent(in) :: grid
            !! grid with nodal velocities
        class(shape_type), intent(in) :: shape
            !! shape function
        real(wp), intent(in) :: x(:), lp(:)
            !! particle position [m] and half size [m]
        real(wp), intent(out) :: gradv(3, 3)
            !! velocity gradient [1/s]
        real(wp), intent(out), optional :: v(:)
            !! interpolated velocity (dim) [m/s]

        type(stencil_type) :: st
        integer :: c, a

        call shape%evaluate(grid, x, lp, st)
        gradv = 0.0_wp
        do c = 1, st%count
            do a = 1, grid%dim
                gradv(1:grid%dim, a) = gradv(1:grid%dim, a) + grid%velocity(:, st%node(c))*st%dw(a, c)
            end do
        end do
        if (present(v)) then
            v = 0.0_wp
            do c = 1, st%count
                v = v + st%w(c)*grid%velocity(:, st%node(c))
            end do
        end if
    end subroutine velocity_gradient

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

    !> Linear index of the grid cell holding position x (clamped to the grid).
    pure integer function cell_of(grid, x)
        type(grid_type), intent(in) :: grid
            !! the grid
        real(wp), intent(in) :: x(:)
            !! position [m]
        integer :: a, i, stride
        cell_of = 1
        stride = 1
        do a = 1, grid%dim
            i = int(floor((x(a) - grid%origin(a))/grid%dx))
            i = min(max(i, 0), grid%ncells(a) - 1)
            cell_of = cell_of + i*stride
            stride = stride*grid%ncells(a)
        end do
    end function cell_of

    !> Velocity that particle p gives node id in a transfer: v_p, plus C_p (x_i - x_p) with
    !> APIC (Jiang et al. 2015; for multilinear and GIMP weights C_p is the gradient of the
    !> nodal velocity field at the particle, as the inertia-tensor form is singular there).
    pure function particle_velocity(grid, particles, p, id) result(v)
        type(grid_type), intent(in) :: grid
            !! grid
        type(particles_type), intent(in) :: particles
            !! particles
        integer, intent(in) :: p, id
            !! particle and node
        real(wp) :: v(grid%dim)

        real(wp) :: xi(3)

        v = particles%v(:, p)
        if (.not. allocated(particles%affine)) return
        xi = node_position(grid, id)
        v = v + matmul(particles%affine(:, :, p), xi(1:grid%dim) - particles%x(:, p))
    end function particle_velocity

    !> Whether a particle of mass m is alone on the nodes of its stencil (each node with a
    !> weight has its mass from this particle, to round-off).
    pure logical function alone(grid, m, st)
        type(grid_type), intent(in) :: grid
            !! grid with nodal masses
        real(wp), intent(in) :: m
            !! particle mass [kg]
        type(stencil_type), intent(in) :: st
            !! stencil of the particle
        integer :: c
        alone = .true.
        do c = 1, st%count
            if (st%w(c) <= 0.0_wp) cycle
            if (grid%mass(st%node(c)) > (1.0_wp + 1.0e-9_wp)*m*st%w(c)) then
                alone = .false.
                return
            end if
        end do
    end function alone

    !> Unit vector along axis a.
    pure function unit(a, dim) result(e)
        integer, intent(in) :: a, dim
        real(wp) :: e(dim)
        e = 0.0_wp
        e(a) = 1.0_wp
    end function unit

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
