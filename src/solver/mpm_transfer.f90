!> The particle and grid passes of one explicit step.
!>
!> Particle-to-grid (P2G) scatters mass, momentum and forces to the nodes; the nodal update
!> integrates the momentum with damping and boundary conditions; grid-to-particle (G2P)
!> gathers accelerations and velocities back; the stress update uses the nodal velocities
!> chosen by the scheme. Each pass is one procedure; the scheme (USF/USL/MUSL) only orders
!> them (see mpm_solver).
module mpm_transfer
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_numerical
    use mpm_grid, only: grid_type
    use mpm_particles, only: particles_type
    use mpm_shape, only: shape_type, stencil_type
    use mpm_material, only: material_holder_type
    use mpm_stress, only: double_contraction
    use mpm_case, only: damping_local
    implicit none
    private
    public :: reset_grid, p2g, nodal_velocity, integrate_nodes, g2p, move_particles, remap_momentum
    public :: update_stress

contains

    !> Zero the nodal fields before a P2G pass.
    subroutine reset_grid(grid)
        type(grid_type), intent(inout) :: grid
            !! the grid

        grid%mass = 0.0_wp
        grid%momentum = 0.0_wp
        grid%fint = 0.0_wp
        grid%fext = 0.0_wp
    end subroutine reset_grid

    !> Scatter particle mass, momentum and gravity (and the internal force when asked).
    !>
    !> f_int,i = - sum_p V_p sigma_p . grad N_i(x_p); in 2D only the in-plane components.
    subroutine p2g(grid, particles, shape, gravity, with_mass, with_fint)
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

        integer :: p, c, id, dim
        type(stencil_type) :: st
        real(wp) :: w, mw, f(3)

        dim = grid%dim
        do p = 1, particles%n
            call shape%evaluate(grid, particles%x(:, p), particles%lp(:, p), st)
            do c = 1, st%count
                id = st%node(c)
                w = st%w(c)
                if (with_mass) then
                    mw = particles%mass(p)*w
                    grid%mass(id) = grid%mass(id) + mw
                    grid%momentum(:, id) = grid%momentum(:, id) + mw*particles%v(:, p)
                    grid%fext(:, id) = grid%fext(:, id) + mw*gravity(1:dim)
                end if
                if (with_fint) then
                    call internal_force(particles%stress(:, p), st%dw(:, c), dim, f)
                    grid%fint(:, id) = grid%fint(:, id) - particles%volume(p)*f(1:dim)
                end if
            end do
        end do
    end subroutine p2g

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

    !> Nodal velocity v_i = p_i / m_i with the boundary constraints applied.
    subroutine nodal_velocity(grid)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set

        integer :: i

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
    !> unbalanced force and v the nodal velocity at the start of the step. Returns the
    !> energy the damping removed in this step (positive).
    subroutine integrate_nodes(grid, dt, damping, alpha, damping_work)
        type(grid_type), intent(inout) :: grid
            !! grid with mass, momentum and forces set
        real(wp), intent(in) :: dt
            !! time step [s]
        integer, intent(in) :: damping
            !! case%damping
        real(wp), intent(in) :: alpha
            !! local damping coefficient [-]
        real(wp), intent(out) :: damping_work
            !! energy removed by local damping in this step [J]

        integer :: i
        real(wp) :: f(3), v0(3), fd(3)
        integer :: dim

        dim = grid%dim
        damping_work = 0.0_wp
        do i = 1, grid%nnodes
            if (grid%mass(i) <= 0.0_wp) then
                grid%velocity(:, i) = 0.0_wp
                grid%acceleration(:, i) = 0.0_wp
                cycle
            end if
            f(1:dim) = grid%fint(:, i) + grid%fext(:, i)
            v0(1:dim) = grid%momentum(:, i)/grid%mass(i)
            if (damping == damping_local) then
                fd(1:dim) = -alpha*abs(f(1:dim))*sign(1.0_wp, v0(1:dim))
                where (v0(1:dim) == 0.0_wp) fd(1:dim) = 0.0_wp
                f(1:dim) = f(1:dim) + fd(1:dim)
            end if
            where (grid%constrained(:, i)) f(1:dim) = 0.0_wp
            grid%acceleration(:, i) = f(1:dim)/grid%mass(i)
            grid%momentum(:, i) = grid%momentum(:, i) + dt*f(1:dim)
            where (grid%constrained(:, i)) grid%momentum(:, i) = 0.0_wp
            grid%velocity(:, i) = grid%momentum(:, i)/grid%mass(i)
            if (damping == damping_local) then
                where (grid%constrained(:, i)) fd(1:dim) = 0.0_wp
                damping_work = damping_work - dt*sum(fd(1:dim)*0.5_wp*(v0(1:dim) &
                    + grid%velocity(:, i)))
            end if
        end do
    end subroutine integrate_nodes

    !> Gather nodal accelerations and velocities: v_p += dt sum N_i a_i (FLIP), and the
    !> position increment dx_p = dt sum N_i v_i, applied later by move_particles so that every
    !> pass of a step uses the shape functions at the start-of-step positions.
    subroutine g2p(grid, particles, shape, dt, dxp)
        type(grid_type), intent(in) :: grid
            !! grid after the nodal update
        type(particles_type), intent(inout) :: particles
            !! particles whose velocities are updated
        class(shape_type), intent(in) :: shape
            !! shape function
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(out) :: dxp(:, :)
            !! position increment of each particle (dim, n) [m]

        integer :: p, c, dim
        type(stencil_type) :: st
        real(wp) :: a(3), v(3)

        dim = grid%dim
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(grid, particles, shape, dt, dim, dxp) private(p, c, st, a, v)
        do p = 1, particles%n
            call shape%evaluate(grid, particles%x(:, p), particles%lp(:, p), st)
            a = 0.0_wp
            v = 0.0_wp
            do c = 1, st%count
                a(1:dim) = a(1:dim) + st%w(c)*grid%acceleration(:, st%node(c))
                v(1:dim) = v(1:dim) + st%w(c)*grid%velocity(:, st%node(c))
            end do
            particles%v(:, p) = particles%v(:, p) + dt*a(1:dim)
            dxp(:, p) = dt*v(1:dim)
        end do
        !$omp end parallel do
    end subroutine g2p

    !> Apply the position increments of the step; fails (exit_numerical) when a particle
    !> leaves the grid or its position is not finite.
    subroutine move_particles(grid, particles, dxp, error)
        type(grid_type), intent(in) :: grid
            !! grid (its extent)
        type(particles_type), intent(inout) :: particles
            !! particles to move
        real(wp), intent(in) :: dxp(:, :)
            !! position increments (dim, n) [m]
        type(error_type), allocatable, intent(out) :: error
            !! set when a particle leaves the grid

        integer :: p, dim, bad
        real(wp) :: lo(3), hi(3)

        dim = grid%dim
        lo = grid%origin
        hi = grid%origin + grid%dx*real(grid%nn - 1, wp)
        bad = 0
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(particles, dxp, dim, lo, hi) private(p) reduction(max: bad)
        do p = 1, particles%n
            particles%x(:, p) = particles%x(:, p) + dxp(:, p)
            particles%u(:, p) = particles%u(:, p) + dxp(:, p)
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

    !> Comma-separated short form of a vector, for messages.
    function vector_text(v) result(text)
        real(wp), intent(in) :: v(:)
        character(len=:), allocatable :: text

        character(len=24) :: buf
        integer :: i

        text = ""
        do i = 1, size(v)
            write (buf, "(es11.4)") v(i)
            text = text//trim(adjustl(buf))
            if (i < size(v)) text = text//", "
        end do
    end function vector_text

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
                    + st%w(c)*particles%mass(p)*particles%v(:, p)
            end do
        end do
        call nodal_velocity(grid)
    end subroutine remap_momentum

    !> Stress update from the nodal velocities in grid%velocity.
    !>
    !> L = sum_i v_i (x) grad N_i; strain increment D dt, spin W dt; F <- (I + L dt) F;
    !> V = det(F) V0; GIMP half-sizes lp = lp0 F_aa (contiguous particle GIMP). Returns the
    !> work of the stresses over the step (strain energy increment).
    !>
    !> Like every pass of a step, it evaluates the shape functions at the start-of-step
    !> positions (particles move at the end of the step).
    subroutine update_stress(grid, particles, shape, materials, dt, strain_work)
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
        real(wp), intent(out) :: strain_work
            !! sum_p V_p sigma_mid : d_eps [J] (per metre in 2D)

        integer :: p, c, dim, ns, a
        type(stencil_type) :: st
        real(wp) :: gradv(3, 3), de(6), omega(3), sold(6), dF(3, 3), jac

        dim = grid%dim
        ns = particles%nstress
        strain_work = 0.0_wp
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(grid, particles, shape, materials, dt, dim, ns) &
        !$omp private(p, c, st, gradv, de, omega, sold, dF, jac, a) reduction(+: strain_work)
        do p = 1, particles%n
            call shape%evaluate(grid, particles%x(:, p), particles%lp(:, p), st)
            gradv = 0.0_wp
            do c = 1, st%count
                do a = 1, dim
                    gradv(1:dim, a) = gradv(1:dim, a) + grid%velocity(:, st%node(c))*st%dw(a, c)
                end do
            end do
            ! gradv(i, j) = d v_i / d x_j
            de = 0.0_wp
            omega = 0.0_wp
            de(1) = gradv(1, 1)*dt
            de(2) = gradv(2, 2)*dt
            de(3) = gradv(3, 3)*dt
            de(4) = 0.5_wp*(gradv(1, 2) + gradv(2, 1))*dt
            omega(1) = 0.5_wp*(gradv(1, 2) - gradv(2, 1))*dt
            if (dim == 3) then
                de(5) = 0.5_wp*(gradv(2, 3) + gradv(3, 2))*dt
                de(6) = 0.5_wp*(gradv(3, 1) + gradv(1, 3))*dt
                omega(2) = 0.5_wp*(gradv(2, 3) - gradv(3, 2))*dt
                omega(3) = 0.5_wp*(gradv(3, 1) - gradv(1, 3))*dt
            end if
            sold(1:ns) = particles%stress(:, p)
            call materials(particles%material(p))%m%update_stress(particles%stress(:, p), &
                de(1:ns), omega, dt, particles%state(:, p))
            particles%strain(:, p) = particles%strain(:, p) + de(1:ns)
            ! deformation gradient, volume and particle domain
            dF = 0.0_wp
            do a = 1, dim
                dF(a, a) = 1.0_wp
            end do
            dF(1:dim, 1:dim) = dF(1:dim, 1:dim) + dt*gradv(1:dim, 1:dim)
            particles%f(:, :, p) = matmul(dF(1:dim, 1:dim), particles%f(:, :, p))
            jac = determinant(particles%f(:, :, p), dim)
            particles%volume(p) = jac*particles%volume0(p)
            do a = 1, dim
                particles%lp(a, p) = particles%lp0(a, p)*abs(particles%f(a, a, p))
            end do
            strain_work = strain_work + particles%volume(p)*0.5_wp &
                *double_contraction(sold(1:ns) + particles%stress(:, p), de(1:ns))
        end do
        !$omp end parallel do
    end subroutine update_stress

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
