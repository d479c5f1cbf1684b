!> The model in time that the solver advances (simulation_type), what a run starts from
!> besides its case (start_type), the phases a step is timed in, and the two small services
!> every layer of the solver shares: agreeing on a failure across images, and whether a text
!> setting is given.
module mpm_simulation
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type
    use mpm_case, only: case_type
    use mpm_grid, only: grid_type
    use mpm_particles, only: particles_type
    use mpm_decomposition, only: decomposition_type
    use mpm_parallel, only: agree_on_failure
    use mpm_shape, only: shape_type
    use mpm_material, only: material_holder_type
    use mpm_stencil, only: stencils_type
    use mpm_energy, only: energies_type
    use mpm_pore_water, only: seepage_type
    implicit none
    private
    public :: simulation_type, start_type, agree, has_text
    public :: nphases, phase_names, phase_stencils, phase_p2g, phase_nodal, phase_g2p, &
        phase_stress, phase_other, phase_output

    integer, parameter :: nphases = 7
        !! phases of a step timed separately (summary, make bench)
    integer, parameter :: phase_stencils = 1, phase_p2g = 2, phase_nodal = 3, phase_g2p = 4, &
        phase_stress = 5, phase_other = 6, phase_output = 7
    character(len=*), parameter :: phase_names(nphases) = [character(len=8) :: &
        "sorting", "P2G", "nodal", "G2P", "stress", "other", "output"]
        !! sorting (shape functions, particle order by cell layer and chunks); P2G (scatters);
        !! nodal (nodal update); G2P (velocities, positions (USL, USF), the MUSL remap);
        !! stress (stress update, MUSL: positions); other: time step, guard, energies; output

    !> A model in time: case, grid, particles, materials and the clock.
    type :: simulation_type
        type(case_type) :: case
            !! resolved case
        type(grid_type) :: grid
            !! background grid
        type(particles_type) :: particles
            !! material points
        type(material_holder_type), allocatable :: materials(:)
            !! constitutive models, in case order
        class(shape_type), allocatable :: shape
            !! shape function
        real(wp), allocatable :: wave_speed(:)
            !! P-wave speed of each material [m/s] (the largest of its particles' at the start,
            !! when it follows the stress: `speed_varies`)
        logical, allocatable :: speed_varies(:)
            !! whether the P-wave speed of each material follows the particle's stress
            !! (material_type%wave_speed_at)
        real(wp) :: face_reaction(3, 2, 3) = 0.0_wp
            !! force each face (side, axis) applied on the material over the last step, over
            !! the whole grid: the impulse of a velocity face / dt, zero for the others [N; N/m
            !! in 2D]
        real(wp), allocatable :: region_reaction(:, :)
            !! force each region of prescribed_motion applied on the material over the last
            !! step, over the whole grid (dim, regions) [N; N/m in 2D]
        real(wp), allocatable :: time_step_limit(:)
            !! other stable-step limit of each material (viscosity), huge when none [s]
        type(stencils_type) :: stencils
            !! shape functions of the step, particle order and scatter chunks
        type(seepage_type) :: seepage
            !! the pore water of saturated soils (`on` false in a dry case)
        type(decomposition_type) :: dec
            !! this image's part of the grid (the whole grid on one image)
        real(wp) :: phase_time(nphases) = 0.0_wp
            !! wall time spent in each phase since the start [s]
        real(wp) :: time = 0.0_wp
            !! simulated time [s]
        integer(i8) :: step = 0
            !! steps done
        real(wp) :: dt = 0.0_wp
            !! time step of the last step [s]
        type(energies_type) :: energy
            !! energy terms, updated every step
        real(wp) :: energy_floor = 0.0_wp
            !! smallest energy scale of the blow-up guard (floor_strain) [J]
        real(wp) :: kinetic_previous = 0.0_wp
            !! kinetic energy of the previous step (kinetic damping) [J]
        real(wp), allocatable :: terrain_corner(:, :, :)
            !! (3, 3, triangles) corners of the terrain surface as read (contact.type =
            !! "terrain_stl"): each new slab grid indexes it again
        logical :: one_pass = .false.
            !! the last particle pass of a step scatters the next step's P2G (solver.one_pass;
            !! USL and MUSL without F-bar, tensor-product shape functions, one image)
        logical :: scatter_ready = .false.
            !! in a one-pass step, the grid holds the P2G of the next step, the stencils are
            !! those of the particles' positions, and stencils%order is the order of that P2G
        real(wp) :: next_grid_kinetic = 0.0_wp
            !! in a one-pass step, the kinetic energy of the nodes of that P2G [J]
        integer, allocatable :: scatter_order(:)
            !! a restart of a one-pass run: the particle order of the P2G of its first step
            !! (that of the step before the checkpoint)
    end type simulation_type

    !> What a simulation starts from besides its case: the data of the files the case names
    !> (a state file, a checkpoint, the terrain surface), read by the set-up layer
    !> (mpm_setup), since the solver reads no file.
    type :: start_type
        logical :: loaded = .false.
            !! the particles come from a state file (load_state) or a checkpoint
        logical :: restart = .false.
            !! from a checkpoint: the run goes on at its time and step, displacements kept
        type(particles_type) :: particles
            !! the particles read (every particle of the file, on every image)
        real(wp) :: time = 0.0_wp
            !! simulated time of the state [s]
        integer :: step = 0
            !! time step number of the state
        real(wp), allocatable :: terrain_corner(:, :, :)
            !! (3, 3, triangles) corners of the terrain surface, contact.type = "terrain_stl" [m]
    end type start_type

contains

    !> True when an optional text setting is present and not empty.
    pure logical function has_text(text)
        character(len=:), allocatable, intent(in) :: text
        has_text = .false.
        if (allocated(text)) has_text = len(text) > 0
    end function has_text

    !> Make a failure of any image the failure of all (collective): every image returns the
    !> error, and only the one that reports it keeps a message (one message per run).
    subroutine agree(error)
        type(error_type), allocatable, intent(inout) :: error
            !! this image's failure, if any; on return the run's

        integer :: code
        logical :: reporter

        code = 0
        if (allocated(error)) code = error%code
        call agree_on_failure(code, reporter)
        if (code == 0) return
        if (.not. allocated(error)) allocate (error)
        error%code = code
        if (.not. reporter) error%message = ""
    end subroutine agree
end module mpm_simulation
