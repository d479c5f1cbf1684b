!> The explicit MPM solver: builds a model from a case and advances it in time.
!>
!> One step (see docs/architecture.md):
!>   stencils -> P2G (mass, momentum, forces) -> nodal update (gravity, damping, boundaries,
!>   integration) -> G2P (velocities; positions, except MUSL) -> stress update (MUSL:
!>   positions) -> checks (blow-up guard, particles that left the grid).
!> The scheme only chooses where the stress update happens and which nodal velocities it
!> sees: USF before the momentum update, USL after it with v_i^{n+1}, MUSL after it with
!> nodal velocities remapped from the updated particle velocities.
module mpm_solver
    use mpm_kinds, only: wp, i8
    use mpm_strings, only: vector_text, text_or, int_text
    use mpm_error, only: error_type, fatal_error, exit_numerical, exit_input, exit_other
    use mpm_case, only: case_type, scheme_usl, scheme_musl, damping_kinetic, damping_local
    use mpm_case_output_fields, only: output_fields
    use mpm_case_stability, only: p_wave_speed, viscous_time_step, water_wave_term
    use mpm_particles, only: particles_type, particle_number, move_particles, &
        particle_field_type, particle_field_count, particle_field, held_written, &
        release_field
    use mpm_bodies, only: create_particles
    use mpm_decomposition, only: new_decomposition
    use mpm_parallel, only: image_count, sum_over_images, max_over_images, min_over_images
    use mpm_shape, only: full_shape_type
    use mpm_shape_factory, only: new_shape
    use mpm_material, only: nwork_kinds, work_viscous
    use mpm_pore_water, only: new_seepage, seepage_start, seepage_step, to_effective, to_total, &
        water_energy
    use mpm_case_materials, only: material_laws, state_variable_count
    use mpm_state, only: run_record_type
    use mpm_contact_loads, only: face_loads, take_face_loads, face_node_count, terrain_loads, &
        take_terrain_loads
    use mpm_stencil, only: compute_stencils, sort_stencils
    use mpm_grid, only: fold_periodic
    use mpm_boundary, only: face_nodes_type
    use mpm_case_domain, only: axis_names
    use mpm_transfer, only: p2g, p2g_options_type, g2p, motion_type, report_lost, update_stress, &
        nstress_sums
    use mpm_kernel_nodal, only: nnodal_sums, nodal_friction, &
        nodal_boundary, nodal_rigid, nodal_kinetic
    use mpm_kernel_contact, only: keep_contact_start, contact_particle_work
    use mpm_halo, only: halo_sum, halo_box, halo_contact_gaps, settle_light_nodes, fold_light
    use mpm_step_passes, only: step_passes, grid_velocity, update_nodes, xpic_field, pass_xpic, &
        face_velocities, &
        pass_p2g, &
        pass_p2g_mass, pass_start_velocity, pass_p2g_force, pass_nodes, pass_g2p, &
        pass_g2p_stress, pass_g2p_remap, pass_stress, pass_stress_move
    use mpm_clock, only: wall_time
    use mpm_energy, only: energies_type, energy_total, energy_residual, energy_scale, &
        energy_record, energies_from_record, nenergy_record, step_energies
    use mpm_simulation, only: simulation_type, start_type, agree, has_text, nphases, &
        phase_names, phase_stencils, phase_p2g, phase_nodal, phase_g2p, phase_stress, &
        phase_other, phase_output
    use mpm_loads, only: assign_loads, apply_loads
    use mpm_motion, only: hold_regions, release_regions, region_count, has_rigid_bodies
    use mpm_kernel_rigid, only: body_particle_velocities, body_particle_positions
    use mpm_solver_slabs, only: slab_grid, terrain_contact, rebalance, decompose_bodies, &
        decompose_loaded, migrate_particles
    implicit none
    private
    public :: simulation_type, new_simulation, advance, stable_time_step, energies_type
    public :: start_type
    public :: compute_energies, has_text, agree, contact_loads, resume_simulation
    public :: start_energy_balance, energy_residual, energy_total, energy_scale, &
        energy_record, energies_from_record, nenergy_record
    public :: nphases, phase_names, phase_stencils, phase_p2g, phase_nodal, phase_g2p, &
        phase_stress, phase_other, phase_output

    real(wp), parameter :: empty_node_fraction = 1.0e-9_wp
        !! a node of at most this fraction of the lightest particle's mass is empty (at rest):
        !! round-off level (the cpGIMP weights lose about 1e-16 / l of their value), far
        !! below any node a particle really reaches
    real(wp), parameter :: light_node_fraction = 1.0e-3_wp
        !! a node of at most this fraction of the mass of a node inside the material
        !! (rho dx**dim, rho the smallest particle density) is light: slaved to its heavy
        !! neighbours (mpm_kernel_light). A node that a particle reaches only with the tail
        !! of its weights otherwise gives that particle its own stress back as an
        !! acceleration of its own (the torn root of the bspline2 cantilever)
    integer, parameter :: sum_block = 4096
        !! particles per partial sum of the energies (fixed order with any thread count)

    real(wp), parameter :: floor_strain = 1.0e-4_wp
        !! the guard's smallest energy scale is the elastic energy of a uniform strain of this
        !! size in every particle, 1/2 m c_p^2 floor_strain^2 summed (a run at rest is not
        !! stopped on the round-off of its energies) [-]

contains

    !> Build the model of a case: grid, materials, shape function and particles (from the
    !> bodies, or those of `start` when the case continues a state file or a checkpoint).
    subroutine new_simulation(sim, case, error, start)
        type(simulation_type), intent(out) :: sim
            !! the simulation
        type(case_type), intent(in) :: case
            !! resolved case
        type(error_type), allocatable, intent(out) :: error
            !! set on allocation failure, or when a file the case names was not read
        type(start_type), intent(inout), optional :: start
            !! the data of the files the case names (mpm_setup::read_start); its particles
            !! move into the simulation (a checkpoint's with its time and step; the rest of
            !! the run record is set by resume_simulation)

        real(wp) :: lightest, density
        integer :: i, k, stat, nstate
        logical :: loaded, restart
        type(particle_field_type) :: described
        type(face_nodes_type) :: lower
        character(len=256) :: msg

        sim%case = case
        call material_laws(case%materials, sim%materials)
        allocate (sim%wave_speed(size(sim%materials)), sim%time_step_limit(size(sim%materials)))
        allocate (sim%speed_varies(size(sim%materials)))
        nstate = state_variable_count(case%materials)
        do i = 1, size(sim%materials)
            sim%wave_speed(i) = p_wave_speed(case%materials(i))
            sim%time_step_limit(i) = viscous_time_step(case%materials(i), case%domain%dx, case%dim)
            sim%speed_varies(i) = sim%materials(i)%m%speed_varies()
        end do
        call new_shape(sim%shape, trim(case%solver%shape_function), error, &
            text_or(case%file, "?"))
        if (allocated(error)) return
        if (image_count() > 1 .and. case%domain%has_springs(case%dim)) then
            call fatal_error(error, case%file//": the Kelvin-Voigt faces of this case (an " &
                //"absorbing face with kn and kt) run on one image: their springs' stretch is " &
                //"kept per node of this image's grid, which a run on "//int_text(image_count()) &
                //" images does not trade yet; run it without cafrun (threads: " &
                //"OMP_NUM_THREADS)", exit_input)
            return
        end if
        if (image_count() > 1 .and. has_rigid_bodies(case)) then
            call fatal_error(error, case%file//": the rigid bodies of this case (materials of " &
                //'type "rigid") run on one image: the motion of a body is summed over all its ' &
                //"nodes in the middle of a step, which a run on "//int_text(image_count()) &
                //" images does not do yet; run it without cafrun (threads: OMP_NUM_THREADS)", &
                exit_input)
            return
        end if
        loaded = .false.
        restart = .false.
        if (present(start)) then
            loaded = start%loaded
            restart = start%restart
        end if
        if (.not. loaded .and. has_text(case%load_state)) then
            call fatal_error(error, case%file//": new_simulation: the state file of "// &
                "load_state was not read (mpm_setup::read_start reads it)", exit_other)
            return
        end if
        if (restart) then
            call move_particles(start%particles, sim%particles, error)
            if (allocated(error)) return
            sim%time = start%time
            sim%step = start%step
            call decompose_loaded(sim, error)
            if (allocated(error)) return
        else if (loaded) then
            call move_particles(start%particles, sim%particles, error)
            if (allocated(error)) return
            ! a new run starts from the loaded state: displacements count from here
            sim%particles%u = 0.0_wp
            ! on several images: each keeps the particles of its slab (any number of images)
            call decompose_loaded(sim, error)
            if (allocated(error)) return
        else if (image_count() > 1) then
            call decompose_bodies(sim, error)
            if (allocated(error)) return
            call create_particles(case, sim%particles, error, nstate, [sim%dec%axis, &
                sim%dec%cell_lo, sim%dec%cell_hi])
            if (allocated(error)) return
        else
            call new_decomposition(sim%dec, case, 1, 1, [integer(i8) ::], error)
            call create_particles(case, sim%particles, error, nstate)
            if (allocated(error)) return
        end if
        ! a material whose stiffness follows the stress: its wave speed for the contact
        ! window, the guard's energy floor and messages is the largest of its particles' at the
        ! start (the time step follows each particle's, stable_time_step)
        if (any(sim%speed_varies)) call starting_wave_speeds(sim)
        ! this image's grid: the whole grid, or its slab with the ghost cells
        call slab_grid(sim, error)
        if (allocated(error)) return
        if (sim%dec%axis > 0) then
            lower = case%domain%nodes(1, sim%dec%axis, case%dim)
            if (lower%periodic) then
                call fatal_error(error, case%file//': the "periodic" faces of axis '// &
                    axis_names(sim%dec%axis:sim%dec%axis)//" are cut among the "// &
                    int_text(image_count())//" images, which do not tie the faces across " &
                    //"them yet; run it on one image (threads: OMP_NUM_THREADS) or make " &
                    //"another axis the longest", exit_input)
                return
            end if
        end if
        ! the pore pressures of saturated soils (pore_water), and their total stresses
        call new_seepage(sim%seepage, case, sim%grid, sim%particles, error)
        if (allocated(error)) return
        if (case%contact%type == "terrain_stl") then
            call terrain_contact(sim, error, start)
            if (allocated(error)) return
        end if
        ! a case stores what it writes: a field held only for output (the accumulated strain,
        ! the displacement) only when an output field shows it or a state file keeps it
        do k = 1, particle_field_count()
            described = particle_field(k)
            if (described%held /= held_written .or. has_text(case%save_state)) cycle
            if (any(case%output%fields .and. output_fields%source == described%name)) cycle
            ! the displacement of a rigid body (history.csv) is that of its particles
            if (described%name == "u" .and. has_rigid_bodies(case)) cycle
            call release_field(sim%particles, k)
        end do
        ! the particles that carry the tractions and point loads (a checkpoint keeps its own)
        if (.not. restart) then
            call assign_loads(case, sim%particles, error)
            call agree(error)
            if (allocated(error)) return
        end if
        ! the force of the constraints on each node, for the grid output
        sim%grid%keep_reaction = case%output%grid
        ! the same threshold on every image: the shared nodes get the same update
        lightest = huge(1.0_wp)
        if (sim%particles%n > 0) lightest = minval(sim%particles%mass)
        call min_over_images(lightest)
        if (lightest < huge(1.0_wp)) sim%grid%small_mass = empty_node_fraction*lightest
        ! light nodes: on a cut grid each is treated by one image, which trades its folds
        ! and slaved values over the shared layers (mpm_kernel_light)
        density = huge(1.0_wp)
        if (sim%particles%n > 0) density = minval(sim%particles%mass/sim%particles%volume0)
        call min_over_images(density)
        sim%grid%light_mass = 0.0_wp
        if (density < huge(1.0_wp)) sim%grid%light_mass = &
            max(sim%grid%small_mass, light_node_fraction*density*case%domain%dx**case%dim)
        ! APIC affine velocities: kept from a state file of an APIC run, zero otherwise (a
        ! uniform velocity per body); dropped when this stage does not use APIC
        if (.not. case%solver%apic .and. allocated(sim%particles%affine)) then
            deallocate (sim%particles%affine)
        end if
        if (case%solver%apic .and. .not. allocated(sim%particles%affine)) then
            allocate (sim%particles%affine(case%dim, case%dim, sim%particles%n), stat=stat, &
                errmsg=msg)
            if (stat /= 0) then
                call fatal_error(error, "cannot allocate the APIC affine velocities: "//trim(msg))
                return
            end if
            sim%particles%affine = 0.0_wp
        end if
        ! one pass over the particles per step where the scheme allows it: the P2G of the
        ! next step needs no more than the particle itself once it has moved (not F-bar's
        ! cell means, not USF's two scatters), stencils that are tensor products (CPDI
        ! evaluates all particles at once), no halo to trade before the scatter, and no pore
        ! water (its pressures change after the stress pass, with the step's stencils)
        sim%one_pass = case%solver%one_pass .and. .not. case%solver%fbar .and. &
            (case%solver%scheme == scheme_usl .or. case%solver%scheme == scheme_musl) .and. &
            image_count() == 1 .and. .not. sim%seepage%on
        select type (shape => sim%shape)
        class is (full_shape_type)
            sim%one_pass = .false.
        class default
            ! tensor products: their stencils are evaluated block by block (restencil)
        end select
        call start_energy_balance(sim)
    end subroutine new_simulation

    !> Start the energy balance from the particles as they are: kinetic and elastic energy
    !> (the `initial` term), every other term zero. new_simulation calls it; a driver that
    !> sets velocities or stresses after new_simulation calls it again. Collective.
    subroutine start_energy_balance(sim)
        type(simulation_type), intent(inout) :: sim
            !! the simulation

        integer :: p, b, nb, k, mat
        real(wp) :: density(1), none(0, 1), floor, s(6, 1)
        real(wp), allocatable :: partial(:, :)

        sim%energy = energies_type()
        sim%energy%kinetic = kinetic_energy(sim%particles)
        nb = (sim%particles%n + sum_block - 1)/sum_block
        allocate (partial(nwork_kinds + 1, nb))
        associate (particles => sim%particles)
            do b = 1, nb
                partial(:, b) = 0.0_wp
                do p = (b - 1)*sum_block + 1, min(b*sum_block, particles%n)
                    mat = particles%material(p)
                    ! the effective stress of a saturated soil
                    s(1:particles%nstress, 1) = particles%stress(:, p)
                    if (sim%seepage%on) then
                        if (sim%seepage%porosity(mat) > 0.0_wp) s(1:3, 1) = s(1:3, 1) &
                            + particles%pore_pressure(p)
                    end if
                    if (particles%nstate > 0) then
                        call sim%materials(mat)%m%elastic_energy_block(1, &
                            s(1:particles%nstress, :), particles%state(:, p:p), density)
                    else
                        call sim%materials(mat)%m%elastic_energy_block(1, &
                            s(1:particles%nstress, :), none, density)
                    end if
                    k = sim%materials(mat)%m%work_kind()
                    partial(k, b) = partial(k, b) + density(1)*particles%volume(p)
                    partial(nwork_kinds + 1, b) = partial(nwork_kinds + 1, b) + 0.5_wp &
                        *particles%mass(p)*(floor_strain*sim%wave_speed(mat))**2
                end do
            end do
        end associate
        floor = 0.0_wp
        do b = 1, nb
            sim%energy%stored = sim%energy%stored + partial(1:nwork_kinds, b)
            floor = floor + partial(nwork_kinds + 1, b)
        end do
        ! the compressed pore water's, with the viscous terms (mpm_pore_water)
        sim%energy%stored(work_viscous) = sim%energy%stored(work_viscous) &
            + water_energy(sim%seepage, sim%particles)
        call sum_over_images(sim%energy%kinetic)
        call sum_over_images(sim%energy%stored)
        call sum_over_images(floor)
        sim%energy%elastic = sum(sim%energy%stored)
        sim%energy%initial = sim%energy%kinetic + sim%energy%elastic
        sim%energy_floor = max(floor, tiny(1.0_wp))
        sim%kinetic_previous = sim%energy%kinetic
    end subroutine start_energy_balance

    !> Continue a run from a checkpoint (after new_simulation with `restart`): the energy
    !> terms, the guard's scale, the last step and the running contact loads, as they were.
    !> Collective.
    subroutine resume_simulation(sim, run, error)
        type(simulation_type), intent(inout) :: sim
            !! the simulation, particles from the checkpoint
        type(run_record_type), intent(in) :: run
            !! the checkpoint's run record
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_input) when the loads do not fit the grid

        integer(i8), allocatable :: node(:)
        real(wp), allocatable :: load(:)
        logical :: complete

        sim%dt = run%dt
        sim%energy = energies_from_record(run%energy)
        sim%kinetic_previous = run%kinetic_previous
        ! the terrain pairs of this grid, to compare with the checkpoint's
        call terrain_loads(sim%case, sim%grid, sim%dec, node, load)
        complete = size(node) == size(run%terrain_node)
        if (complete) complete = all(node == run%terrain_node)
        if (size(run%face_load) /= face_node_count(sim%case) .or. .not. complete) then
            call fatal_error(error, "the contact loads of the checkpoint do not fit the "// &
                "grid of the case (the boundaries or the terrain changed?)", exit_input)
            return
        end if
        call take_face_loads(sim%case, sim%grid, sim%dec, run%face_load)
        call take_terrain_loads(sim%case, sim%grid, sim%dec, run%terrain_node, &
            run%terrain_load, complete)
        ! the springs' stretch of the Kelvin-Voigt faces
        if (sim%case%domain%has_springs(sim%case%dim)) then
            if (.not. allocated(run%acting_disp)) then
                call fatal_error(error, "the checkpoint has no stretch of the Kelvin-Voigt " &
                    //"faces' springs (written before the case had them?)", exit_input)
                return
            end if
            if (size(run%acting_disp) /= size(sim%grid%acting_disp)) then
                call fatal_error(error, "the springs' stretch of the checkpoint does not fit " &
                    //"the faces of the case (the boundaries changed?)", exit_input)
                return
            end if
            sim%grid%acting_disp = reshape(run%acting_disp, shape(sim%grid%acting_disp))
        end if
        ! the order of the P2G the checkpoint's last step did for the next one (a one-pass run
        ! on one image); without it the first step sorts, and the sums differ in round-off
        if (allocated(run%scatter_order) .and. sim%one_pass) then
            if (.not. is_permutation(run%scatter_order, sim%particles%n)) then
                call fatal_error(error, "the run record's scatter_order is not an order of "// &
                    "the checkpoint's "//int_text(sim%particles%n)//" particles (the file "// &
                    "is damaged)", exit_input)
                return
            end if
            sim%scatter_order = run%scatter_order
        end if
    end subroutine resume_simulation

    !> Whether `order` holds each of 1 .. n once.
    pure logical function is_permutation(order, n)
        integer, intent(in) :: order(:)
            !! the order
        integer, intent(in) :: n
            !! its length

        logical, allocatable :: seen(:)
        integer :: q

        is_permutation = size(order) == n
        if (.not. is_permutation) return
        allocate (seen(n))
        seen = .false.
        do q = 1, n
            if (order(q) < 1 .or. order(q) > n) then
                is_permutation = .false.
                return
            end if
            if (seen(order(q))) then
                is_permutation = .false.
                return
            end if
            seen(order(q)) = .true.
        end do
    end function is_permutation

    !> The running normal loads of the contacts, for a checkpoint (collective): every
    !> frictional face node of the whole grid (face_loads), and every terrain pair by node
    !> of the whole grid (terrain_loads).
    subroutine contact_loads(sim, face_load, terrain_node, terrain_load)
        type(simulation_type), intent(in) :: sim
            !! the simulation
        real(wp), allocatable, intent(out) :: face_load(:)
            !! loads of the frictional face nodes [N s]
        integer(i8), allocatable, intent(out) :: terrain_node(:)
            !! node of each terrain pair in the whole grid, ascending
        real(wp), allocatable, intent(out) :: terrain_load(:)
            !! loads of the terrain pairs [N s]

        call face_loads(sim%case, sim%grid, sim%dec, face_load)
        call terrain_loads(sim%case, sim%grid, sim%dec, terrain_node, terrain_load)
    end subroutine contact_loads



    !> sim%wave_speed of each material whose stiffness follows the stress: the largest
    !> wave_speed_at of its particles as they start, at least its wave_speed().
    subroutine starting_wave_speeds(sim)
        type(simulation_type), intent(inout) :: sim
            !! the simulation, its particles created or loaded

        integer :: p, mat
        real(wp) :: speed

        do mat = 1, size(sim%materials)
            if (.not. sim%speed_varies(mat)) cycle
            speed = sim%wave_speed(mat)
            do p = 1, sim%particles%n
                if (sim%particles%material(p) /= mat) cycle
                speed = max(speed, speed_at(sim, p))
            end do
            call max_over_images(speed)
            sim%wave_speed(mat) = speed
        end do
    end subroutine starting_wave_speeds

    !> The P-wave speed of particle p of a material whose stiffness follows the stress, at its
    !> effective stress and state; undrained in a saturated soil, sqrt(c^2 + K_w / (n rho)).
    real(wp) function speed_at(sim, p)
        type(simulation_type), intent(in) :: sim
            !! the simulation
        integer, intent(in) :: p
            !! the particle

        integer :: mat
        real(wp) :: s(6)

        mat = sim%particles%material(p)
        if (.not. allocated(sim%particles%pore_pressure)) then
            speed_at = sim%materials(mat)%m%wave_speed_at(sim%particles%stress(:, p), &
                sim%particles%state(:, p))
            return
        end if
        s(1:sim%particles%nstress) = sim%particles%stress(:, p)
        s(1:3) = s(1:3) + sim%particles%pore_pressure(p)
        speed_at = sim%materials(mat)%m%wave_speed_at(s(1:sim%particles%nstress), &
            sim%particles%state(:, p))
        speed_at = sqrt(speed_at**2 + water_wave_term(sim%case%materials(mat)))
    end function speed_at

    !> Time step: the fixed dt of the case, or C dx / max_p (c_p + |v_p|), c_p at the
    !> particle's stress for a material whose stiffness follows it.
    real(wp) function stable_time_step(sim)
        type(simulation_type), intent(in) :: sim
            !! the simulation

        integer :: p, mat
        real(wp) :: speed

        if (sim%case%time%dt > 0.0_wp) then
            stable_time_step = sim%case%time%dt
            return
        end if
        speed = 0.0_wp
        if (any(sim%speed_varies)) then
            !$omp parallel do default(none) schedule(static) shared(sim) private(p, mat) &
            !$omp reduction(max: speed)
            do p = 1, sim%particles%n
                mat = sim%particles%material(p)
                if (sim%speed_varies(mat)) then
                    speed = max(speed, speed_at(sim, p) + norm2(sim%particles%v(:, p)))
                else
                    speed = max(speed, sim%wave_speed(mat) + norm2(sim%particles%v(:, p)))
                end if
            end do
            !$omp end parallel do
        else
            !$omp parallel do default(none) schedule(static) shared(sim) private(p) &
            !$omp reduction(max: speed)
            do p = 1, sim%particles%n
                speed = max(speed, sim%wave_speed(sim%particles%material(p)) &
                    + norm2(sim%particles%v(:, p)))
            end do
            !$omp end parallel do
        end if
        call max_over_images(speed)
        stable_time_step = sim%case%time%cfl*min(sim%case%domain%dx/max(speed, tiny(1.0_wp)), &
            minval(sim%time_step_limit))
    end function stable_time_step

    !> Advance the simulation by one step of length dt: the scheme's passes in order
    !> (step_passes), then the energy sums, the checks and the clock.
    subroutine advance(sim, dt, error)
        type(simulation_type), intent(inout) :: sim
            !! the simulation
        real(wp), intent(in) :: dt
            !! time step [s]
        type(error_type), allocatable, intent(out) :: error
            !! set on a numerical failure (exit_numerical)

        integer, parameter :: nsums = 6 + nstress_sums + nnodal_sums
            !! energy sums of a step (the grid's kinetic energies and the blend's loss last);
            !! the faces' impulses follow them
        real(wp) :: work(nstress_sums), nodal_work(nnodal_sums), clock, kinetic, stopped, &
            grid_kinetic(2), blend_loss, water_work, water_stored
        real(wp), allocatable :: sums(:)
        integer :: scheme, k, nregions
        integer, allocatable :: passes(:)
        logical :: grid_energy, one_pass, ready, rigid
        type(motion_type) :: motion
        type(energies_type) :: next

        scheme = sim%case%solver%scheme
        ! the loads at the step's start: the particles' extra body force
        call apply_loads(sim%case, sim%particles, sim%time)
        ! the particles' volumes at the start (pore water: the skeleton's volume change)
        call seepage_start(sim%seepage, sim%particles)
        ! one pass: the last particle pass scatters the next step's P2G (a prescribed body
        ! force may change between the steps: its P2G stays in its own pass; the particles of
        ! a rigid body take its velocity after G2P)
        rigid = has_rigid_bodies(sim%case)
        one_pass = sim%one_pass .and. .not. allocated(sim%particles%body_force) .and. &
            .not. rigid
        ready = one_pass .and. sim%scatter_ready
        sim%scatter_ready = .false.
        ! the nodes' kinetic energies are booked only when G2P gives the particles the nodal
        ! velocities (step_energies); FLIP runs do not pay for the two sums
        grid_energy = sim%case%solver%apic .or. sim%case%solver%flip_fraction == 0.0_wp
        stopped = 0.0_wp
        grid_kinetic = 0.0_wp
        clock = wall_time()
        if (ready) then
            ! the stencils of the positions and the P2G come from the last step: the order
            ! and the chunks of this step's positions
            call sort_stencils(sim%stencils, sim%grid, sim%particles)
        else if (allocated(sim%scatter_order) .and. one_pass) then
            ! a restart: the P2G in the order of the step before the checkpoint
            call compute_stencils(sim%stencils, sim%grid, sim%particles, sim%shape, error, &
                margin=1, order=sim%scatter_order)
        else
            call compute_stencils(sim%stencils, sim%grid, sim%particles, sim%shape, error, &
                cells=sim%case%solver%fbar, margin=merge(1, 0, one_pass))
        end if
        if (allocated(error)) return
        ! the nodes of the regions of prescribed_motion and of the rigid bodies, held for the
        ! step
        call hold_regions(sim%case, sim%grid, sim%time, sim%particles, sim%stencils, error)
        ! a contradiction is found on the image of its node: every image stops (collective)
        if (region_count(sim%case) > 0) call agree(error)
        if (allocated(error)) return
        ! the faces whose velocity changes in time at their velocity of the step's start (the
        ! start velocities of USF and USL; the nodal update takes them to the end's)
        if (sim%grid%prescribed_varies) call face_velocities(sim%grid, sim%case%domain%face, &
            sim%time, sim%time)
        call lap(sim, phase_stencils, clock)
        passes = step_passes(scheme, sim%case%solver%fbar, xpic=sim%case%solver%xpic)
        associate (grid => sim%grid, particles => sim%particles, stc => sim%stencils, &
                   fbar => sim%case%solver%fbar)
            do k = 1, size(passes)
                select case (passes(k))
                case (pass_p2g_mass)
                    ! USF: mass and momentum only, for the velocities of its stress update
                    call scatter_to_nodes(sim, p2g_options_type(mass=.true., fbar=fbar))
                    if (grid_energy) grid_kinetic(1) = nodal_kinetic(grid)
                    if (.not. grid_energy) call keep_contact_start(grid)
                    call lap(sim, phase_p2g, clock)
                case (pass_start_velocity)
                    ! USF: the constraints act on the momentum of the step here: what they stop
                    call grid_velocity(grid, dt)
                    if (grid_energy) stopped = grid_kinetic(1) - nodal_kinetic(grid)
                    call lap(sim, phase_nodal, clock)
                case (pass_p2g_force)
                    ! USF: the internal force of the updated stresses
                    call scatter_to_nodes(sim, p2g_options_type(fint=.true., fbar=fbar))
                    call lap(sim, phase_p2g, clock)
                case (pass_p2g)
                    if (ready) then
                        ! done by the last pass of the step before (finish_next_p2g)
                        grid_kinetic(1) = sim%next_grid_kinetic
                    else
                        call scatter_to_nodes(sim, p2g_options_type(mass=.true., fint=.true., &
                            fbar=fbar))
                        if (grid_energy) grid_kinetic(1) = nodal_kinetic(grid)
                        if (.not. grid_energy) call keep_contact_start(grid)
                        if (allocated(sim%scatter_order)) then
                            ! a restart's P2G done: the order of this step's positions
                            deallocate (sim%scatter_order)
                            call sort_stencils(stc, grid, particles)
                        end if
                    end if
                    call lap(sim, phase_p2g, clock)
                case (pass_nodes)
                    call update_nodes(grid, sim%case%domain%face, sim%time, dt, &
                        sim%case%gravity, local_damping=sim%case%damping%type == damping_local, &
                        alpha=sim%case%damping%value, dissipated=nodal_work)
                    nodal_work(nodal_boundary) = nodal_work(nodal_boundary) + stopped
                    if (grid_energy) grid_kinetic(2) = nodal_kinetic(grid)
                    ! FLIP without a remap: the contacts' work on the particles at the updated
                    ! momentum
                    if (.not. grid_energy .and. scheme /= scheme_musl) call &
                        contact_particle_work(grid, nodal_work(nodal_friction), &
                        nodal_work(nodal_boundary))
                    call lap(sim, phase_nodal, clock)
                case (pass_xpic)
                    ! the start velocities G2P gives the particles, their null space removed
                    call xpic_field(grid, particles, stc, dt, sim%case%solver%xpic_order, &
                        sim%shape%halo_width())
                    call lap(sim, phase_nodal, clock)
                case (pass_g2p_stress)
                    ! USL without F-bar: the stress update needs the nodal velocities of the
                    ! moves, in the same pass
                    call to_effective(sim%seepage, particles)
                    if (one_pass) then
                        call g2p(grid, particles, stc, dt, sim%case%solver%flip_fraction, &
                            sim%case%gravity, remap=.false., motion=motion, kinetic=kinetic, &
                            materials=sim%materials, strain_work=work, blend_loss=blend_loss, &
                            xpic=sim%case%solver%xpic, shape=sim%shape)
                        call lap(sim, phase_g2p, clock)
                        call finish_next_p2g(sim, grid_energy, motion%lost > 0)
                        call lap(sim, phase_p2g, clock)
                    else
                        call g2p(grid, particles, stc, dt, sim%case%solver%flip_fraction, &
                            sim%case%gravity, remap=.false., motion=motion, kinetic=kinetic, &
                            materials=sim%materials, strain_work=work, blend_loss=blend_loss, &
                            xpic=sim%case%solver%xpic)
                        if (rigid) call rigid_velocities(sim, kinetic, nodal_work, grid_energy)
                        call lap(sim, phase_g2p, clock)
                    end if
                    call to_total(sim%seepage, particles)
                case (pass_g2p)
                    ! USL with F-bar, USF: the particles move here
                    call g2p(grid, particles, stc, dt, sim%case%solver%flip_fraction, &
                        sim%case%gravity, remap=.false., motion=motion, kinetic=kinetic, &
                        blend_loss=blend_loss, xpic=sim%case%solver%xpic)
                    if (rigid) call rigid_velocities(sim, kinetic, nodal_work, grid_energy)
                    call lap(sim, phase_g2p, clock)
                case (pass_g2p_remap)
                    ! MUSL: the same pass maps the updated particle momentum back to the nodes;
                    ! the particles move in the stress update
                    call g2p(grid, particles, stc, dt, sim%case%solver%flip_fraction, &
                        sim%case%gravity, remap=.true., motion=motion, kinetic=kinetic, &
                        blend_loss=blend_loss, xpic=sim%case%solver%xpic)
                    if (rigid) call rigid_velocities(sim, kinetic, nodal_work, grid_energy)
                    ! the remapped momentum of the shared nodes, then the velocities of the
                    ! remap
                    call halo_sum(grid, sim%shape%halo_width(), momentum=.true.)
                    if (grid_energy) then
                        ! the particles slide with these velocities: friction works at them
                        call grid_velocity(grid, dt, nodal_work(nodal_friction))
                    else
                        ! FLIP: what the contact impulses took from the particles, with the
                        ! momentum of their new velocities (the light nodes' in their masters)
                        call fold_light(grid, grid%momentum)
                        call contact_particle_work(grid, nodal_work(nodal_friction), &
                            nodal_work(nodal_boundary))
                        call grid_velocity(grid, dt)
                    end if
                    call lap(sim, phase_g2p, clock)
                case (pass_stress)
                    ! USF before the momentum; USL with F-bar after the moves (its own pass)
                    call to_effective(sim%seepage, particles)
                    call update_stress(grid, particles, stc, sim%materials, dt, fbar=fbar, &
                        strain_work=work, gravity=sim%case%gravity)
                    call to_total(sim%seepage, particles)
                    call lap(sim, phase_stress, clock)
                case (pass_stress_move)
                    ! MUSL: the particles move with the remapped velocities that strain them:
                    ! moved with the velocities of the nodal update instead, the difference (dt
                    ! times the nodal acceleration) feeds particle noise under tension that
                    ! FLIP never damps (growth ~ sigma dt / (rho dx^2), see
                    ! docs/accuracy-vs-cost.md)
                    call to_effective(sim%seepage, particles)
                    if (one_pass) then
                        call update_stress(grid, particles, stc, sim%materials, dt, fbar=fbar, &
                            strain_work=work, gravity=sim%case%gravity, motion=motion, &
                            shape=sim%shape)
                        call lap(sim, phase_stress, clock)
                        call finish_next_p2g(sim, grid_energy, motion%lost > 0)
                        call lap(sim, phase_p2g, clock)
                    else
                        call update_stress(grid, particles, stc, sim%materials, dt, fbar=fbar, &
                            strain_work=work, gravity=sim%case%gravity, motion=motion)
                        call lap(sim, phase_stress, clock)
                    end if
                    call to_total(sim%seepage, particles)
                case default
                    call fatal_error(error, "advance: pass "//int_text(passes(k))// &
                        " of step_passes has no branch (a defect of mpm-geo)", exit_other)
                    return
                end select
            end do
        end associate
        ! the pore pressures: the water's flow and the skeleton's volume change of the step;
        ! its work and stored energy go with the viscous terms (mpm_pore_water)
        if (sim%seepage%on) then
            call seepage_step(sim%seepage, sim%grid, sim%particles, sim%stencils, dt, &
                sim%case%gravity, water_work, water_stored)
            work(work_viscous) = work(work_viscous) + water_work
            work(nwork_kinds + work_viscous) = work(nwork_kinds + work_viscous) + water_stored
            call lap(sim, phase_stress, clock)
        end if
        ! the rigid bodies' particles move together
        if (rigid) call body_particle_positions(sim%grid, sim%particles, dt)
        call release_regions(sim%grid)
        ! sums over the images, in one reduction (the faces' and regions' impulses last)
        nregions = 0
        if (allocated(sim%grid%region_impulse)) nregions = size(sim%grid%region_impulse)
        allocate (sums(nsums + size(sim%grid%face_impulse) + nregions))
        sums(:nsums + size(sim%grid%face_impulse)) = [kinetic, motion%potential, &
            motion%load_work, work, nodal_work, grid_kinetic, blend_loss, &
            reshape(sim%grid%face_impulse, [size(sim%grid%face_impulse)])]
        if (nregions > 0) sums(nsums + size(sim%grid%face_impulse) + 1:) = &
            reshape(sim%grid%region_impulse, [nregions])
        call sum_over_images(sums)
        next = step_energies(sim%energy, sums(1:nsums), grid_velocities=grid_energy)
        sim%face_reaction = reshape(sums(nsums + 1:nsums + size(sim%grid%face_impulse)), &
            shape(sim%face_reaction))/dt
        if (nregions > 0) sim%region_reaction = reshape(sums(nsums &
            + size(sim%grid%face_impulse) + 1:), shape(sim%grid%region_impulse))/dt
        ! the blow-up guard speaks first, so an unstable run is reported as such rather than
        ! as the particles it throws out of the grid
        call check_blow_up(sim, motion, next, error)
        if (.not. allocated(error) .and. motion%lost > 0) then
            ! the corners of the whole grid (this image's is a slab of it)
            call report_lost(sim%case%domain%origin, sim%case%domain%origin + sim%case%domain%dx* &
                real(merge(sim%case%domain%ncells, 0, [1, 2, 3] <= sim%case%dim), wp), sim%particles, &
                motion%lost, error)
            error%message = step_prefix(sim)//error%message
        end if
        call agree(error)
        if (allocated(error)) return
        sim%time = sim%time + dt
        sim%step = sim%step + 1
        sim%dt = dt
        sim%energy = next
        if (sim%case%damping%type == damping_kinetic) call kinetic_damping(sim)
        ! on several images: particles that left the slab go to their new image, and now
        ! and then the cuts follow the particles
        call migrate_particles(sim, error)
        call agree(error)
        if (.not. allocated(error)) call rebalance(sim, error)
        call lap(sim, phase_other, clock)
    end subroutine advance

    !> The particles of the rigid bodies at their bodies' velocities after G2P
    !> (mpm_kernel_rigid): the kinetic energy that changes is theirs; what it takes is stopped
    !> by the rigid constraint (booked with the constraints) in a FLIP step, and the transfer
    !> term's when G2P gives the particles the nodal velocities (it is the nodes' kinetic
    !> energy that G2P did not give them).
    subroutine rigid_velocities(sim, kinetic, nodal_work, grid_energy)
        type(simulation_type), intent(inout) :: sim
            !! the simulation
        real(wp), intent(inout) :: kinetic
            !! kinetic energy of the particles after G2P [J]
        real(wp), intent(inout) :: nodal_work(nnodal_sums)
            !! the nodal sums of the step
        logical, intent(in) :: grid_energy
            !! G2P gives the particles the nodal velocities (APIC, PIC)

        real(wp) :: change

        call body_particle_velocities(sim%grid, sim%particles, change)
        kinetic = kinetic + change
        if (.not. grid_energy) nodal_work(nodal_rigid) = nodal_work(nodal_rigid) - change
    end subroutine rigid_velocities

    !> P2G of the step with the images' halo: with mass, the images first trade the parts of
    !> their boxes of touched nodes in the shared layers (the box of the step's grid work);
    !> after the scatter they add the neighbours' parts of the shared nodes, and take the
    !> smaller contact gap there.
    subroutine scatter_to_nodes(sim, opts)
        type(simulation_type), intent(inout), target :: sim
            !! the simulation, its stencils computed for the step
        type(p2g_options_type), intent(in) :: opts
            !! what to scatter

        integer :: layers, box_lo(3), box_hi(3)

        layers = sim%shape%halo_width()
        box_lo = sim%stencils%box_lo
        box_hi = sim%stencils%box_hi
        if (opts%mass) call halo_box(sim%grid, layers, box_lo, box_hi)
        call p2g(sim%grid, sim%particles, sim%stencils, opts, box_lo, box_hi)
        call halo_sum(sim%grid, layers, mass=opts%mass, momentum=opts%mass, fint=opts%fint, &
            fext=opts%mass .and. allocated(sim%particles%body_force))
        ! the upper nodes of periodic faces to their lower ones
        call fold_periodic(sim%grid)
        if (opts%mass) call halo_contact_gaps(sim%grid, layers)
        if (opts%mass) call settle_light_nodes(sim%grid, layers)
    end subroutine scatter_to_nodes

    !> The end of the next step's P2G that the last particle pass of a one-pass step did
    !> (the part of scatter_to_nodes after the scatter), and what the next step takes from it:
    !> the nodes' kinetic energy, or the contact velocities at its start (FLIP). Nothing when
    !> a particle left the grid (the step fails).
    subroutine finish_next_p2g(sim, grid_energy, lost)
        type(simulation_type), intent(inout) :: sim
            !! the simulation, its grid holding the scattered sums
        logical, intent(in) :: grid_energy
            !! the nodes' kinetic energies are booked (step_energies)
        logical, intent(in) :: lost
            !! a particle left the grid in the pass

        integer :: layers

        if (lost) return
        layers = sim%shape%halo_width()
        call halo_sum(sim%grid, layers, mass=.true., momentum=.true., fint=.true., fext=.false.)
        call fold_periodic(sim%grid)
        call halo_contact_gaps(sim%grid, layers)
        call settle_light_nodes(sim%grid, layers)
        if (grid_energy) sim%next_grid_kinetic = nodal_kinetic(sim%grid)
        if (.not. grid_energy) call keep_contact_start(sim%grid)
        sim%scatter_ready = .true.
    end subroutine finish_next_p2g


    !> Add the wall time since `clock` to a phase and restart the clock.
    subroutine lap(sim, phase, clock)
        type(simulation_type), intent(inout) :: sim
        integer, intent(in) :: phase
        real(wp), intent(inout) :: clock

        real(wp) :: now

        now = wall_time()
        sim%phase_time(phase) = sim%phase_time(phase) + (now - clock)
        clock = now
    end subroutine lap

    !> Stop a run that blows up: a particle that moved more than a cell in one step, a
    !> kinetic energy or an energy residual that is not finite, or an energy residual (the
    !> energy the discretisation created, energy_residual) above guard.energy_factor times
    !> the energy scale of the run (energy_scale: what the run was given, initial kinetic and
    !> elastic energy and the work of gravity and loads so far). A physical run cannot create
    !> energy; an explicit run past its stability limit creates it at a growing rate, while
    !> its own energies grow with it (a bound on a multiple of the largest energy so far is
    !> passed late or never). The message names the step, the particle (the fastest, with
    !> its volume change), its position and the quantity.
    subroutine check_blow_up(sim, motion, next, error)
        type(simulation_type), intent(in) :: sim
            !! the simulation after a step
        type(motion_type), intent(in) :: motion
            !! the largest move of the step
        type(energies_type), intent(in) :: next
            !! the energy terms after the step
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_numerical) when the run blew up

        integer :: p, worst
        real(wp) :: speed, fastest, created, scale
        character(len=700) :: msg

        associate (ke => next%kinetic, particles => sim%particles)
            ! a stable explicit step moves no material point by more than a cell
            if (motion%jump > sim%case%domain%dx) then
                p = motion%jump_particle
                write (msg, "(a,i0,a,a,a,es10.3,a,es10.3,a)") &
                    "the run became unstable: particle ", particle_number(particles, p), &
                    " (now at ", &
                    trim(vector_text(particles%x(:, p))), ") m moved ", &
                    motion%jump_length, " m in one step, more than a cell (dx = ", &
                    sim%case%domain%dx, " m)"
                call fatal_error(error, step_prefix(sim)//trim(msg)// &
                    "; reduce time.dt or time.cfl", exit_numerical)
                return
            end if
            created = energy_residual(next)
            scale = energy_scale(next, sim%energy_floor)
            if (ke <= huge(1.0_wp) .and. abs(created) <= huge(1.0_wp) .and. &
                .not. created > sim%case%guard%energy_factor*scale) return
            ! the particle that shows it: the first with a non-finite velocity or stress,
            ! else the fastest
            worst = 0
            fastest = -1.0_wp
            do p = 1, particles%n
                if (.not. (all(abs(particles%v(:, p)) <= huge(1.0_wp)) .and. &
                           all(abs(particles%stress(:, p)) <= huge(1.0_wp)))) then
                    worst = p
                    exit
                end if
                speed = norm2(particles%v(:, p))
                if (speed > fastest) then
                    fastest = speed
                    worst = p
                end if
            end do
            if (worst == 0) then
                ! no particle on this image: another image names one
                msg = "the run became unstable (see the other images)"
            else if (.not. (ke <= huge(1.0_wp) .and. abs(created) <= huge(1.0_wp))) then
                write (msg, "(a,i0,a,a,a)") "the run became unstable: particle ", &
                    particle_number(particles, worst), &
                    " at (", trim(vector_text(particles%x(:, worst))), &
                    ") m has a velocity or stress that is not finite"
            else
                write (msg, "(a,es10.3,a,g0.4,a,es10.3,a,i0,a,a,a,es10.3,a,es10.3,a,f0.3,a)") &
                    "the run became unstable: it created energy, the energy residual ", &
                    created, " J is more than guard.energy_factor = ", &
                    sim%case%guard%energy_factor, " times the energy scale of the run (", &
                    scale, " J: initial kinetic + elastic energy, largest |work of gravity "// &
                    "and loads|); fastest particle ", particle_number(particles, worst), &
                    " at (", trim(vector_text(particles%x(:, worst))), ") m, |v| = ", &
                    fastest, " m/s (P-wave speed ", sim%wave_speed(particles%material(worst)), &
                    " m/s), volume ", particles%volume(worst)/particles%volume0(worst), &
                    " times its start"
            end if
        end associate
        call fatal_error(error, step_prefix(sim)//trim(msg)//"; reduce time.dt or time.cfl", &
            exit_numerical)
    end subroutine check_blow_up

    !> "step N, t = T s: " for messages.
    function step_prefix(sim) result(prefix)
        type(simulation_type), intent(in) :: sim
        character(len=:), allocatable :: prefix

        character(len=64) :: buf

        write (buf, "(a,i0,a,es12.5,a)") "step ", sim%step + 1, ", t = ", sim%time, " s: "
        prefix = trim(buf)//" "
    end function step_prefix

    !> Dynamic relaxation: zero every velocity when the kinetic energy has passed a peak.
    subroutine kinetic_damping(sim)
        type(simulation_type), intent(inout) :: sim

        if (sim%energy%kinetic < sim%kinetic_previous) then
            sim%energy%damping = sim%energy%damping + sim%energy%kinetic
            sim%particles%v = 0.0_wp
            sim%energy%kinetic = 0.0_wp
            ! the momenta of a one-pass step's P2G are those of the velocities before
            sim%scatter_ready = .false.
        end if
        sim%kinetic_previous = sim%energy%kinetic
    end subroutine kinetic_damping

    !> Sum of 1/2 m |v|^2 over the particles [J].
    real(wp) function kinetic_energy(particles)
        type(particles_type), intent(in) :: particles

        integer :: p, b, nb
        real(wp), allocatable :: partial(:)

        ! partial sums over fixed blocks, added in block order: the same bits with any number
        ! of threads
        nb = (particles%n + sum_block - 1)/sum_block
        allocate (partial(nb))
        !$omp parallel do default(none) schedule(static) shared(particles, nb, partial) &
        !$omp private(p, b)
        do b = 1, nb
            partial(b) = 0.0_wp
            do p = (b - 1)*sum_block + 1, min(b*sum_block, particles%n)
                partial(b) = partial(b) + 0.5_wp*particles%mass(p)*sum(particles%v(:, p)**2)
            end do
        end do
        !$omp end parallel do
        kinetic_energy = 0.0_wp
        do b = 1, nb
            kinetic_energy = kinetic_energy + partial(b)
        end do
    end function kinetic_energy

    !> Refresh the kinetic energy from the particles (the potential energy is summed from the
    !> moves of every step).
    subroutine compute_energies(sim)
        type(simulation_type), intent(inout) :: sim
            !! the simulation

        sim%energy%kinetic = kinetic_energy(sim%particles)
        call sum_over_images(sim%energy%kinetic)
    end subroutine compute_energies

end module mpm_solver
