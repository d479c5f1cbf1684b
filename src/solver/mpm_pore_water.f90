!> Pore water of saturated soils: the pore pressure of each particle, its flow through the
!> skeleton (Darcy) and its share of the stress, in the explicit step (u-p formulation).
!>
!> Each particle of a saturated material (`pore_water.materials`) carries a pore pressure p
!> (compression positive); `particles%stress` is the total stress sigma = sigma' - p I, which
!> P2G turns into the internal force, while the material's law updates the effective stress
!> sigma' (the solver adds p I before the stress pass and takes it off after: to_effective,
!> to_total). After the stress pass, `seepage_step` updates p from the mass balance of the
!> water, n / K_w dp/dt = - div v - div q with Darcy's flux q = - (k / gamma_w) (grad p -
!> rho_w g), on the grid, with the stencils of the step:
!>
!> - P2G: each node's storage S_i = sum_p N_ip V_p n / K_w, its pressure P_i = sum_p N_ip
!>   V_p n / K_w h_p / S_i of the particles' h = p - rho_w g . x (q = - (k / gamma_w) grad h:
!>   a hydrostatic state, h uniform, maps to no flow, also where the projection is one-sided
!>   at a face) and the volume change of the skeleton dV_i = sum_p N_ip dV_p (the volume
!>   change of the step's stress pass); a node on a drained face takes the pressure of the
!>   face;
!> - the flux of each particle from the gradient of the nodal h, q_p, and each node's
!>   inflow Q_i = sum_p V_p grad N_ip . q_p (no flow leaves through a face or a free surface
!>   of the material unless a node holds its pressure: impermeable by default);
!> - each node's change dP_i = (dt Q_i - dV_i) / S_i (none on a drained face, whose nodes hold
!>   its pressure); each particle's p grows by sum_i N_ip dP_i (FLIP of the nodal change),
!>   except next to a drained face, where a particle takes sum_i N_ip (P_i + dP_i) + rho_w
!>   g . x_p (the
!>   boundary value on its nodes, as in a finite element: FLIP would pull the particles of
!>   the boundary cell below the face's pressure); its total stress falls by the same.
!>
!> Volume changes and flow are balanced on the nodes (the nodal volume change smooths the
!> pressure over the particles of a cell, as F-bar does the volume). The time step takes the
!> undrained wave speed, sqrt(c^2 + K_w / (n rho)), and the diffusion limit dx^2 / (2 dim D)
!> with D = (k / gamma_w) K_w / n (mpm_case_stability). The energy of the water: its work -p
!> dV is booked with the viscous work, its stored energy V n p^2 / (2 K_w) with the viscous
!> materials' elastic energy: the difference is what the flow dissipates (and what drained
!> faces take out), in the `viscous` term of the balance. A dry case holds none of this.
module mpm_pore_water
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_input
    use mpm_strings, only: int_text
    use mpm_case, only: case_type, initial_k0
    use mpm_case_pore_water, only: drain_none, drain_pressure, hydrostatic_pressure
    use mpm_case_stability, only: mobility
    use mpm_case_output_fields, only: output_fields
    use mpm_grid, only: grid_type
    use mpm_particles, only: particles_type, particle_field_count, particle_field, &
        particle_field_type, hold_field, field_held, held_water
    use mpm_stencil, only: stencils_type, particle_nodes
    use mpm_shape, only: max_stencil_nodes
    use mpm_parallel, only: image_count
    implicit none
    private
    public :: seepage_type, new_seepage, seepage_start, seepage_step, to_effective, to_total, &
        water_energy

    !> The pore water of a run: per material its porosity, mobility and the water's bulk
    !> modulus; per node the scratch of the step; per particle the volume at the step's start.
    type :: seepage_type
        logical :: on = .false.
            !! the case has pore water
        real(wp) :: density = 0.0_wp
            !! density of the water rho_w [kg/m3]
        real(wp), allocatable :: porosity(:)
            !! porosity n of each material, 0 for a dry one (materials)
        real(wp), allocatable :: mobility(:)
            !! k / gamma_w of each material [m2/(Pa s)] (materials)
        real(wp), allocatable :: modulus(:)
            !! bulk modulus of the pore water K_w of each material [Pa] (materials)
        logical, allocatable :: drained(:)
            !! whether each node lies on a face with a prescribed pore pressure (nodes)
        real(wp), allocatable :: drained_p(:)
            !! that pressure [Pa] (nodes)
        real(wp), allocatable :: node_weight(:)
            !! rho_w g . x of each node [Pa] (nodes): the pressures are balanced as p - rho_w
            !! g . x, so that a hydrostatic state is one of no flow on the grid too
        real(wp), allocatable :: storage(:), pressure(:), swell(:), inflow(:), change(:)
            !! per node: storage sum N V n / K_w [m3/Pa], pressure [Pa], volume change of
            !! the skeleton [m3], inflow of water [m3/s], change of the pressure [Pa]
        real(wp), allocatable :: volume_start(:)
            !! volume of each particle at the start of the step [m3]
        integer, allocatable :: node(:, :)
            !! scratch of a step: each particle's stencil nodes (count, n)
        real(wp), allocatable :: w(:, :), dw(:, :, :), q(:, :), sums(:, :)
            !! scratch of a step: their weights (count, n) and gradients (3, count, n), each
            !! particle's Darcy flux (3, n), its water work and stored energy (2, n)
    end type seepage_type

contains

    !> The pore water of a case: nothing without `pore_water`. With it: the drained nodes of
    !> the grid, the pore pressure of each particle (held), and, for particles that do not
    !> bring one (a new run, or a state file of a dry stage), the hydrostatic pressure of the
    !> phreatic level; their stress given by the case is then the effective one (with
    !> initial_stress "k0": the vertical total stress of the weight above, the horizontal
    !> K0 times its effective part), and the total stress takes p off.
    subroutine new_seepage(seep, case, grid, particles, error)
        type(seepage_type), intent(out) :: seep
            !! the pore water of the run
        type(case_type), intent(in) :: case
            !! resolved case
        type(grid_type), intent(in) :: grid
            !! the grid (the whole one: pore water runs on one image)
        type(particles_type), intent(inout) :: particles
            !! the particles (created or loaded)
        type(error_type), allocatable, intent(out) :: error
            !! set when the run has several images or memory runs out

        integer :: m, k, side, axis, idx(3), node
        logical :: brought
        real(wp) :: x(3)
        type(particle_field_type) :: described

        if (.not. case%pore_water%on) return
        if (image_count() > 1) then
            call fatal_error(error, case%file//": pore_water runs on one image: the pore " &
                //"pressures are balanced on the nodes of the whole grid, which a run on " &
                //int_text(image_count())//" images does not trade yet; run it without " &
                //"cafrun (threads: OMP_NUM_THREADS)", exit_input)
            return
        end if
        seep%on = .true.
        seep%density = case%pore_water%density
        allocate (seep%porosity(size(case%materials)), seep%mobility(size(case%materials)), &
            seep%modulus(size(case%materials)))
        do m = 1, size(case%materials)
            seep%porosity(m) = case%materials(m)%porosity
            seep%mobility(m) = mobility(case%materials(m))
            seep%modulus(m) = max(case%materials(m)%water_bulk_modulus, tiny(1.0_wp))
        end do
        allocate (seep%drained(grid%nnodes), seep%drained_p(grid%nnodes), &
            seep%storage(grid%nnodes), seep%pressure(grid%nnodes), seep%swell(grid%nnodes), &
            seep%inflow(grid%nnodes), seep%change(grid%nnodes))
        allocate (seep%node_weight(grid%nnodes))
        seep%drained = .false.
        seep%drained_p = 0.0_wp
        do node = 1, grid%nnodes
            idx = 0
            idx(1) = mod(node - 1, grid%nn(1))
            idx(2) = mod((node - 1)/grid%nn(1), grid%nn(2))
            if (grid%dim == 3) idx(3) = (node - 1)/(grid%nn(1)*grid%nn(2))
            x = grid%origin + grid%dx*real(idx, wp)
            seep%node_weight(node) = seep%density*dot_product(case%gravity(1:grid%dim), &
                x(1:grid%dim))
            do axis = 1, grid%dim
                do side = 1, 2
                    if (case%pore_water%face(side, axis) == drain_none) cycle
                    if (idx(axis) /= merge(0, grid%nn(axis) - 1, side == 1)) cycle
                    seep%drained(node) = .true.
                    if (case%pore_water%face(side, axis) == drain_pressure) then
                        seep%drained_p(node) = case%pore_water%face_pressure(side, axis)
                    else
                        seep%drained_p(node) = hydrostatic_pressure(case%pore_water, &
                            grid%dim, case%gravity, x)
                    end if
                end do
            end do
        end do
        allocate (seep%volume_start(particles%n))
        ! the pore pressure, and the effective stress and water velocity when written
        brought = .false.
        do k = 1, particle_field_count()
            described = particle_field(k)
            if (described%held /= held_water) cycle
            if (field_held(particles, k)) then
                if (trim(described%name) == "pore_p") brought = .true.
                cycle
            end if
            if (trim(described%name) /= "pore_p" .and. .not. &
                any(case%output%fields .and. output_fields%source == described%name)) cycle
            call hold_field(particles, k, error)
            if (allocated(error)) return
        end do
        if (.not. brought) call hydrostatic_start(seep, case, grid%dim, particles)
        call fill_outputs(seep, particles)
    end subroutine new_seepage

    !> The pore pressures of the phreatic level and the total stresses of particles that
    !> bring no pore pressure (new_seepage).
    subroutine hydrostatic_start(seep, case, dim, particles)
        type(seepage_type), intent(in) :: seep
            !! the pore water
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: dim
            !! space dimensions
        type(particles_type), intent(inout) :: particles
            !! the particles

        integer :: p, m, a
        real(wp) :: x(3), sv, k0

        do p = 1, particles%n
            m = particles%material(p)
            if (seep%porosity(m) <= 0.0_wp) cycle
            x = 0.0_wp
            x(1:dim) = particles%x(:, p)
            particles%pore_pressure(p) = hydrostatic_pressure(case%pore_water, dim, &
                case%gravity, x)
            if (case%initial_stress%type == initial_k0 .and. .not. from_state(case)) then
                ! the geostatic stress: total vertical, K0 on its effective part
                sv = particles%stress(dim, p)
                k0 = case%initial_stress%k0_material(m)
                do a = 1, 3
                    particles%stress(a, p) = k0*(sv + particles%pore_pressure(p)) &
                        - particles%pore_pressure(p)
                end do
                particles%stress(dim, p) = sv
            else
                particles%stress(1:3, p) = particles%stress(1:3, p) - particles%pore_pressure(p)
            end if
        end do
    end subroutine hydrostatic_start

    !> The effective stress and the water velocity of the particles as they are (when
    !> written): sigma + p I, and the skeleton's velocity before any flow.
    subroutine fill_outputs(seep, particles)
        type(seepage_type), intent(in) :: seep
            !! the pore water
        type(particles_type), intent(inout) :: particles
            !! the particles

        integer :: p

        if (allocated(particles%water_v)) particles%water_v = particles%v
        if (.not. allocated(particles%effective)) return
        particles%effective = particles%stress
        do p = 1, particles%n
            if (seep%porosity(particles%material(p)) <= 0.0_wp) cycle
            particles%effective(1:3, p) = particles%effective(1:3, p) &
                + particles%pore_pressure(p)
        end do
    end subroutine fill_outputs

    !> Whether the case starts from a state file (load_state).
    pure logical function from_state(case)
        type(case_type), intent(in) :: case
        from_state = .false.
        if (allocated(case%load_state)) from_state = len(case%load_state) > 0
    end function from_state

    !> The start of a step: the particles' volumes.
    subroutine seepage_start(seep, particles)
        type(seepage_type), intent(inout) :: seep
            !! the pore water
        type(particles_type), intent(in) :: particles
            !! the particles

        if (.not. seep%on) return
        if (size(seep%volume_start) /= particles%n) then
            deallocate (seep%volume_start)
            allocate (seep%volume_start(particles%n))
        end if
        seep%volume_start = particles%volume
    end subroutine seepage_start

    !> The effective stress for the stress pass: sigma + p I of every saturated particle.
    subroutine to_effective(seep, particles)
        type(seepage_type), intent(in) :: seep
            !! the pore water
        type(particles_type), intent(inout) :: particles
            !! the particles

        call add_pressure(seep, particles, 1.0_wp)
    end subroutine to_effective

    !> The total stress after the stress pass: sigma' - p I of every saturated particle.
    subroutine to_total(seep, particles)
        type(seepage_type), intent(in) :: seep
            !! the pore water
        type(particles_type), intent(inout) :: particles
            !! the particles

        call add_pressure(seep, particles, -1.0_wp)
    end subroutine to_total

    !> sigma + sign p I of every saturated particle (nothing in a dry case).
    subroutine add_pressure(seep, particles, sign)
        type(seepage_type), intent(in) :: seep
            !! the pore water
        type(particles_type), intent(inout) :: particles
            !! the particles
        real(wp), intent(in) :: sign
            !! 1 or -1

        integer :: p

        if (.not. seep%on) return
        !$omp parallel do default(none) schedule(static) shared(seep, particles, sign) private(p)
        do p = 1, particles%n
            if (seep%porosity(particles%material(p)) <= 0.0_wp) cycle
            particles%stress(1:3, p) = particles%stress(1:3, p) + sign*particles%pore_pressure(p)
        end do
        !$omp end parallel do
    end subroutine add_pressure

    !> The pore pressures after the stress pass of a step (see the module): the water's work
    !> over the step and its stored energy at the end, for the energy balance. Serial sums in
    !> particle order: the same bits on any number of threads.
    subroutine seepage_step(seep, grid, particles, stc, dt, gravity, work, stored)
        type(seepage_type), intent(inout) :: seep
            !! the pore water
        type(grid_type), intent(in) :: grid
            !! the grid
        type(particles_type), intent(inout) :: particles
            !! the particles, after the stress pass
        type(stencils_type), intent(in) :: stc
            !! the stencils of the step (start-of-step positions)
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(in) :: gravity(3)
            !! gravitational acceleration [m/s2]
        real(wp), intent(out) :: work
            !! work of the pore pressures on the skeleton's volume change, - p_mid dV [J]
        real(wp), intent(out) :: stored
            !! energy stored in the compressed water at the end, V n p^2 / (2 K_w) [J]

        integer :: p, c, m, dim, i, nc
        integer :: node(max_stencil_nodes)
        real(wp) :: w(max_stencil_nodes), dw(3, max_stencil_nodes), s, dv, grad(3), dp, pold, &
            head
        logical :: drained

        work = 0.0_wp
        stored = 0.0_wp
        if (.not. seep%on) return
        dim = grid%dim
        nc = stc%count
        if (.not. allocated(seep%node)) then
            allocate (seep%node(nc, 0), seep%w(nc, 0), seep%dw(3, nc, 0), seep%q(3, 0), &
                seep%sums(2, 0))
        end if
        if (size(seep%node, 2) < particles%n .or. size(seep%node, 1) /= nc) then
            deallocate (seep%node, seep%w, seep%dw, seep%q, seep%sums)
            allocate (seep%node(nc, particles%n), seep%w(nc, particles%n), &
                seep%dw(3, nc, particles%n), seep%q(3, particles%n), seep%sums(2, particles%n))
        end if
        ! the stencils of the saturated particles, once (each particle on its own: threads)
        !$omp parallel do default(none) schedule(static) shared(seep, particles, stc, nc) &
        !$omp private(p, node, w, dw)
        do p = 1, particles%n
            if (seep%porosity(particles%material(p)) <= 0.0_wp) cycle
            call particle_nodes(stc, p, node, w, dw)
            seep%node(:, p) = node(1:nc)
            seep%w(:, p) = w(1:nc)
            seep%dw(:, :, p) = dw(:, 1:nc)
        end do
        !$omp end parallel do
        seep%storage = 0.0_wp
        seep%pressure = 0.0_wp
        seep%swell = 0.0_wp
        seep%inflow = 0.0_wp
        ! serial sums in particle order: the same bits on any number of threads
        do p = 1, particles%n
            m = particles%material(p)
            if (seep%porosity(m) <= 0.0_wp) cycle
            s = seep%volume_start(p)*seep%porosity(m)/seep%modulus(m)
            dv = particles%volume(p) - seep%volume_start(p)
            head = particles%pore_pressure(p) - seep%density*dot_product(gravity(1:dim), &
                particles%x(:, p))
            do c = 1, nc
                i = seep%node(c, p)
                seep%storage(i) = seep%storage(i) + seep%w(c, p)*s
                seep%pressure(i) = seep%pressure(i) + seep%w(c, p)*s*head
                seep%swell(i) = seep%swell(i) + seep%w(c, p)*dv
            end do
        end do
        ! the tied nodes of periodic faces: the sums on the lower face's node
        do c = 1, grid%nperiodic
            call fold_node(grid%periodic_slave(c), grid%periodic_master(c))
        end do
        do i = 1, grid%nnodes
            if (seep%storage(i) <= 0.0_wp) cycle
            seep%pressure(i) = seep%pressure(i)/seep%storage(i)
            ! a drained node holds the face's pressure
            seep%change(i) = 0.0_wp
            if (seep%drained(i)) seep%pressure(i) = seep%drained_p(i) - seep%node_weight(i)
        end do
        do c = grid%nperiodic, 1, -1
            seep%pressure(grid%periodic_slave(c)) = seep%pressure(grid%periodic_master(c))
        end do
        ! Darcy's flux of each particle (threads), then the nodes' inflow (serial)
        !$omp parallel do default(none) schedule(static) shared(seep, particles, nc, dim) &
        !$omp private(p, m, c, grad)
        do p = 1, particles%n
            m = particles%material(p)
            if (seep%porosity(m) <= 0.0_wp) then
                if (allocated(particles%water_v)) particles%water_v(:, p) = particles%v(:, p)
                cycle
            end if
            grad = 0.0_wp
            do c = 1, nc
                grad(1:dim) = grad(1:dim) + seep%dw(1:dim, c, p)*seep%pressure(seep%node(c, p))
            end do
            seep%q(:, p) = 0.0_wp
            seep%q(1:dim, p) = -seep%mobility(m)*grad(1:dim)
            if (allocated(particles%water_v)) particles%water_v(:, p) = particles%v(:, p) &
                + seep%q(1:dim, p)/seep%porosity(m)
        end do
        !$omp end parallel do
        do p = 1, particles%n
            m = particles%material(p)
            if (seep%porosity(m) <= 0.0_wp .or. seep%mobility(m) <= 0.0_wp) cycle
            do c = 1, nc
                i = seep%node(c, p)
                seep%inflow(i) = seep%inflow(i) &
                    + seep%volume_start(p)*dot_product(seep%dw(1:dim, c, p), seep%q(1:dim, p))
            end do
        end do
        do c = 1, grid%nperiodic
            i = grid%periodic_master(c)
            seep%inflow(i) = seep%inflow(i) + seep%inflow(grid%periodic_slave(c))
            seep%inflow(grid%periodic_slave(c)) = 0.0_wp
        end do
        do i = 1, grid%nnodes
            if (seep%storage(i) <= 0.0_wp .or. seep%drained(i)) cycle
            seep%change(i) = (dt*seep%inflow(i) - seep%swell(i))/seep%storage(i)
        end do
        do c = grid%nperiodic, 1, -1
            seep%change(grid%periodic_slave(c)) = seep%change(grid%periodic_master(c))
        end do
        ! each particle's pressure and total stress (threads; the energy sums after, serial)
        !$omp parallel do default(none) schedule(static) shared(seep, particles, nc, dim, gravity) &
        !$omp private(p, m, c, pold, drained, dp, dv)
        do p = 1, particles%n
            m = particles%material(p)
            if (seep%porosity(m) <= 0.0_wp) then
                if (allocated(particles%effective)) particles%effective(:, p) = &
                    particles%stress(:, p)
                seep%sums(:, p) = 0.0_wp
                cycle
            end if
            pold = particles%pore_pressure(p)
            drained = .false.
            do c = 1, nc
                if (seep%w(c, p) > 0.0_wp) drained = drained .or. seep%drained(seep%node(c, p))
            end do
            dp = 0.0_wp
            if (drained) then
                ! next to a drained face: the nodal pressures, the face's held (as in a
                ! finite element with the boundary value on its node)
                do c = 1, nc
                    dp = dp + seep%w(c, p)*(seep%pressure(seep%node(c, p)) &
                        + seep%change(seep%node(c, p)))
                end do
                dp = dp + seep%density*dot_product(gravity(1:dim), particles%x(:, p)) - pold
            else
                ! elsewhere the nodal change (FLIP): no smoothing of the particles' pressures
                do c = 1, nc
                    dp = dp + seep%w(c, p)*seep%change(seep%node(c, p))
                end do
            end if
            particles%pore_pressure(p) = pold + dp
            particles%stress(1:3, p) = particles%stress(1:3, p) - dp
            if (allocated(particles%effective)) then
                particles%effective(:, p) = particles%stress(:, p)
                particles%effective(1:3, p) = particles%effective(1:3, p) &
                    + particles%pore_pressure(p)
            end if
            dv = particles%volume(p) - seep%volume_start(p)
            seep%sums(1, p) = -0.5_wp*(pold + particles%pore_pressure(p))*dv
            seep%sums(2, p) = 0.5_wp*particles%volume(p)*seep%porosity(m)/seep%modulus(m) &
                *particles%pore_pressure(p)**2
        end do
        !$omp end parallel do
        do p = 1, particles%n
            work = work + seep%sums(1, p)
            stored = stored + seep%sums(2, p)
        end do

    contains

        !> The storage, pressure and volume change of node `from` added to node `to`.
        subroutine fold_node(from, to)
            integer, intent(in) :: from, to

            seep%storage(to) = seep%storage(to) + seep%storage(from)
            seep%pressure(to) = seep%pressure(to) + seep%pressure(from)
            seep%swell(to) = seep%swell(to) + seep%swell(from)
            seep%storage(from) = 0.0_wp
            seep%pressure(from) = 0.0_wp
            seep%swell(from) = 0.0_wp
        end subroutine fold_node
    end subroutine seepage_step

    !> The energy stored in the compressed pore water of the particles, V n p^2 / (2 K_w) [J].
    real(wp) function water_energy(seep, particles)
        type(seepage_type), intent(in) :: seep
            !! the pore water
        type(particles_type), intent(in) :: particles
            !! the particles

        integer :: p, m

        water_energy = 0.0_wp
        if (.not. seep%on) return
        do p = 1, particles%n
            m = particles%material(p)
            if (seep%porosity(m) <= 0.0_wp) cycle
            water_energy = water_energy + 0.5_wp*particles%volume(p)*seep%porosity(m) &
                /seep%modulus(m)*particles%pore_pressure(p)**2
        end do
    end function water_energy

end module mpm_pore_water
