!> The resolved description of a simulation case, and the case-file reader interface.
!>
!> `case_type` holds every setting of a run with every default resolved and every value
!> checked; the rest of the code reads settings only from it. The reader itself (JSON keys,
!> strict checks, messages) lives in the submodule `mpm_case_reader`.
module mpm_case
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type
    implicit none
    private
    public :: case_type, material_spec_type, body_spec_type
    public :: read_case_file, read_case_string, case_summary, critical_time_step
    public :: case_key_paths
    public :: bc_free, bc_sliding, bc_fixed, bc_frictional, bc_names
    public :: cone_plane_strain, cone_compression, cone_extension, cone_names
    public :: softening_none, softening_linear, softening_exponential, softening_names
    public :: scheme_usf, scheme_usl, scheme_musl, scheme_names
    public :: shape_linear, shape_cpgimp, shape_names
    public :: damping_none, damping_local, damping_kinetic, damping_names
    public :: dist_regular, dist_random, distribution_names
    public :: field_position, field_displacement, field_velocity, field_stress, field_strain
    public :: field_material, field_mass, field_volume, field_plastic_strain, field_names
    public :: nfields
    public :: p_wave_speed, viscous_time_step, body_subcell_range

    ! Boundary condition of a domain face
    integer, parameter :: bc_free = 0     !! no constraint
    integer, parameter :: bc_sliding = 1  !! normal velocity zero, tangential free
    integer, parameter :: bc_fixed = 2    !! all velocity components zero (no slip, sticking)
    integer, parameter :: bc_frictional = 3
        !! Coulomb friction with coefficient mu; the material may separate from the face
    character(len=*), parameter :: bc_names(0:3) = [character(len=10) :: "free", "sliding", &
        "fixed", "frictional"]

    ! Drucker-Prager cone matched to Mohr-Coulomb
    integer, parameter :: cone_plane_strain = 1  !! same collapse load in plane strain
    integer, parameter :: cone_compression = 2   !! outer cone: through the compression corners
    integer, parameter :: cone_extension = 3     !! inner cone: through the extension corners
    character(len=*), parameter :: cone_names(3) = [character(len=12) :: "plane_strain", &
        "compression", "extension"]

    ! Softening of strength parameters with the accumulated plastic shear strain
    integer, parameter :: softening_none = 0         !! constant strength
    integer, parameter :: softening_linear = 1       !! linear from peak to residual
    integer, parameter :: softening_exponential = 2  !! exponential decay to residual
    character(len=*), parameter :: softening_names(0:2) = [character(len=11) :: "none", &
        "linear", "exponential"]

    ! Update scheme (when the stress is updated within a step)
    integer, parameter :: scheme_usf = 1   !! update stress first
    integer, parameter :: scheme_usl = 2   !! update stress last
    integer, parameter :: scheme_musl = 3  !! modified update stress last
    character(len=*), parameter :: scheme_names(3) = [character(len=4) :: "USF", "USL", "MUSL"]

    ! Shape function
    integer, parameter :: shape_linear = 1  !! bilinear / trilinear hat functions
    integer, parameter :: shape_cpgimp = 2  !! contiguous-particle GIMP
    character(len=*), parameter :: shape_names(2) = [character(len=6) :: "linear", "cpgimp"]

    ! Damping
    integer, parameter :: damping_none = 0     !! no damping
    integer, parameter :: damping_local = 1    !! local (Cundall) damping of nodal forces
    integer, parameter :: damping_kinetic = 2  !! kinetic damping (dynamic relaxation)
    character(len=*), parameter :: damping_names(0:2) = &
        [character(len=7) :: "none", "local", "kinetic"]

    ! Particle distribution inside a cell
    integer, parameter :: dist_regular = 1  !! regular sub-grid of ppc^dim points
    integer, parameter :: dist_random = 2   !! one random point in each sub-cell (seeded)
    character(len=*), parameter :: distribution_names(2) = [character(len=7) :: "regular", "random"]

    ! Output fields
    integer, parameter :: nfields = 9
    integer, parameter :: field_position = 1, field_displacement = 2, field_velocity = 3, &
        field_stress = 4, field_strain = 5, field_material = 6, field_mass = 7, field_volume = 8, &
        field_plastic_strain = 9
    character(len=*), parameter :: field_names(nfields) = [character(len=14) :: "position", &
        "displacement", "velocity", "stress", "strain", "material", "mass", "volume", &
        "plastic_strain"]

    !> One material of the case. Which parameters are used depends on `type`.
    type :: material_spec_type
        character(len=:), allocatable :: name
            !! name used by bodies to refer to this material
        character(len=:), allocatable :: type
            !! constitutive model: "linear_elastic", "mohr_coulomb", "drucker_prager", "newtonian"
        real(wp) :: young = 0.0_wp
            !! Young's modulus E [Pa] (elastic and elasto-plastic types)
        real(wp) :: poisson = 0.0_wp
            !! Poisson's ratio nu [-] (elastic and elasto-plastic types)
        real(wp) :: density = 0.0_wp
            !! mass density rho [kg/m3]
        real(wp) :: friction = 0.0_wp
            !! peak friction angle phi [rad] (input in degrees)
        real(wp) :: cohesion = 0.0_wp
            !! peak cohesion c [Pa]
        real(wp) :: dilatancy = 0.0_wp
            !! peak dilatancy angle psi [rad] (input in degrees), 0 <= psi <= phi
        real(wp) :: tension_cutoff = -1.0_wp
            !! tensile strength: largest mean (DP) or principal (MC) stress allowed [Pa];
            !! negative when not given (then the apex of the cone, c / tan(phi), limits it)
        logical :: separation = .false.
            !! cohesionless separation: dilation at the stress-free apex opens the material,
            !! and compression closes it again before any stress builds (MC and DP, c = 0 or
            !! tension_cutoff = 0)
        integer :: softening = softening_none
            !! softening law of phi, c and psi with the plastic shear strain
        real(wp) :: friction_residual = 0.0_wp
            !! residual friction angle [rad] (softening only)
        real(wp) :: cohesion_residual = 0.0_wp
            !! residual cohesion [Pa] (softening only)
        real(wp) :: dilatancy_residual = 0.0_wp
            !! residual dilatancy angle [rad] (softening only)
        real(wp) :: softening_strain = 0.0_wp
            !! linear: plastic shear strain at which the residual values are reached;
            !! exponential: strain scale eta_0 in x = x_r + (x_p - x_r) exp(-eps_p / eta_0) [-]
        integer :: cone = cone_plane_strain
            !! Drucker-Prager cone matched to the Mohr-Coulomb parameters
        real(wp) :: viscosity = 0.0_wp
            !! dynamic viscosity mu of a Newtonian fluid [Pa s]
        real(wp) :: bulk_modulus = 0.0_wp
            !! bulk modulus K of a Newtonian fluid [Pa] (sets the pressure and the wave speed)
    end type material_spec_type

    !> A body of particles of one material: a box, or the inside of a closed STL surface.
    type :: body_spec_type
        character(len=:), allocatable :: name
            !! name of the body (for messages and output)
        integer :: material = 0
            !! index into case%materials
        real(wp) :: xmin(3) = 0.0_wp
            !! lower corner of the box (of the surface's bounding box for an STL body) [m]
        real(wp) :: xmax(3) = 0.0_wp
            !! upper corner of the box (of the surface's bounding box for an STL body) [m]
        real(wp) :: velocity(3) = 0.0_wp
            !! initial velocity [m/s]
        character(len=:), allocatable :: file
            !! STL file of the closed surface ("" for a box)
        real(wp) :: scale = 1.0_wp
            !! factor applied to the STL coordinates before `offset` [m per unit]
        real(wp) :: offset(3) = 0.0_wp
            !! translation added to the scaled STL coordinates [m]
        real(wp), allocatable :: triangle(:, :, :)
            !! corners (coordinate, corner 1..3, triangle) of the closed surface after scale and
            !! offset; not allocated for a box [m]
        integer(i8) :: particles = -1
            !! particles the body holds, counted by the reader (-1: not counted)
    end type body_spec_type

    !> Every setting of a run, resolved and checked.
    type :: case_type
        character(len=:), allocatable :: file
            !! case file path as given ("<string>" for cases read from text)
        character(len=:), allocatable :: name
            !! case name (default: file name without directory and extension)
        character(len=:), allocatable :: output_dir
            !! output folder (default: outputs/<name>)
        integer :: dim = 2
            !! number of space dimensions (2: plane strain, 3)
        integer :: ncells(3) = 1
            !! cells per direction (ncells(3) = 1 and unused in 2D)
        real(wp) :: dx = 0.0_wp
            !! cell size, equal in every direction [m]
        real(wp) :: origin(3) = 0.0_wp
            !! coordinates of the lowest domain corner [m]
        integer :: bc(2, 3) = bc_free
            !! boundary condition of each face: bc(1, axis) at the min face, bc(2, axis) at max
        real(wp) :: bc_friction(2, 3) = 0.0_wp
            !! Coulomb friction coefficient mu of each frictional face [-]
        integer :: ppc = 2
            !! particles per cell along each direction (ppc**dim per cell)
        integer :: distribution = dist_regular
            !! particle placement inside a cell
        integer :: seed = 1
            !! seed of the random distribution
        type(material_spec_type), allocatable :: materials(:)
            !! materials, in file order
        type(body_spec_type), allocatable :: bodies(:)
            !! bodies, in file order
        real(wp) :: gravity(3) = 0.0_wp
            !! gravitational acceleration [m/s2]
        integer :: scheme = scheme_musl
            !! update scheme
        integer :: shape = shape_cpgimp
            !! shape function
        logical :: apic = .false.
            !! affine particle-in-cell transfer (solver.transfer = "apic") instead of FLIP
        real(wp) :: flip_fraction = 1.0_wp
            !! particle velocity update: this fraction FLIP (v_p + dt a), the rest PIC (the
            !! nodal velocity interpolated) [-]
        logical :: fbar = .false.
            !! F-bar volumetric locking correction: the volume change of each step is averaged
            !! over the particles of a cell (solver.locking_correction = "fbar")
        real(wp) :: dt = 0.0_wp
            !! fixed time step [s]; 0 when the CFL condition sets it
        real(wp) :: cfl = 0.5_wp
            !! CFL factor C in dt = C dx / max_p (c_p + |v_p|) [-]
        logical :: allow_unstable = .false.
            !! accept dt above the critical step or cfl > 1 (stability tests; the blow-up guard
            !! then stops the run)
        real(wp) :: tend = 0.0_wp
            !! end time [s]
        integer :: damping = damping_none
            !! damping type
        real(wp) :: damping_value = 0.0_wp
            !! local damping coefficient alpha [-] (0 <= alpha < 1)
        character(len=:), allocatable :: contact_type
            !! "none" or "terrain_stl" (frictional contact with a rigid surface from an STL file)
        real(wp) :: contact_mu = 0.0_wp
            !! Coulomb friction coefficient of the terrain [-]
        character(len=:), allocatable :: contact_file
            !! STL file of the terrain surface (terrain_stl)
        real(wp) :: contact_scale = 1.0_wp
            !! factor on the STL coordinates (units to metres) [-]
        real(wp) :: contact_offset(3) = 0.0_wp
            !! added to the scaled STL coordinates [m]
        real(wp) :: output_interval = 0.0_wp
            !! time between particle outputs [s]; 0 for no intermediate output
        logical :: output_fields(nfields) = .true.
            !! which particle fields are written
        logical :: output_grid = .false.
            !! also write the grid nodes (mass, velocity)
        logical :: overwrite = .false.
            !! allow writing into an existing output folder
        real(wp) :: history_interval = 0.0_wp
            !! time between lines of the energy history [s]; 0: every output step
        character(len=:), allocatable :: save_state
            !! state file to write at the end ("" for none)
        character(len=:), allocatable :: load_state
            !! state file to start from ("" for none)
        real(wp) :: progress_seconds = 2.0_wp
            !! wall-clock seconds between progress lines [s]
        integer :: checkpoint_steps = 0
            !! steps between two checkpoints; 0: none by step count
        real(wp) :: checkpoint_minutes = 0.0_wp
            !! wall-clock minutes between two checkpoints; 0: none by wall time [min]
        character(len=:), allocatable :: checkpoint_file
            !! checkpoint file; "" for <output_dir>/checkpoint.h5
        logical :: checkpoint_on_signal = .true.
            !! on SIGTERM or SIGINT, write a checkpoint and stop (exit_interrupted)
        real(wp) :: guard_energy_factor = 1.0_wp
            !! the blow-up guard stops a run that created more energy (its energy residual)
            !! than this factor times its energy scale (initial kinetic and elastic energy,
            !! |work of gravity and loads| so far) [-]
        integer :: guard_snapshot_steps = 100
            !! steps between two copies of the state kept in memory, written as the last
            !! healthy state when the guard stops the run; 0: no copy
        character(len=:), allocatable :: text
            !! JSON text of the case file as read (checkpoints keep it); "" from text
    end type case_type

    interface
        !> Read, check and resolve a case file.
        module subroutine read_case_file(path, case, error)
            character(len=*), intent(in) :: path
                !! case file (JSON)
            type(case_type), intent(out) :: case
                !! resolved case
            type(error_type), allocatable, intent(out) :: error
                !! set (code exit_input) on any invalid input
        end subroutine read_case_file

        !> Read, check and resolve a case given as JSON text (tests, tools).
        module subroutine read_case_string(text, case, error, source)
            character(len=*), intent(in) :: text
                !! JSON text of the case
            type(case_type), intent(out) :: case
                !! resolved case
            type(error_type), allocatable, intent(out) :: error
                !! set (code exit_input) on any invalid input
            character(len=*), intent(in), optional :: source
                !! name used for the case in messages and as default case name
        end subroutine read_case_string

        !> A multi-line, human-readable summary of the resolved case (for --check and logs).
        module function case_summary(case) result(text)
            type(case_type), intent(in) :: case
                !! resolved case
            character(len=:), allocatable :: text
                !! summary, lines separated by new_line("a")
        end function case_summary

        !> Every key path the case reader accepts, from the reader's own key lists (the schema
        !> test compares them with docs/case.schema.json). An object's keys are written
        !> "section.key", an array item's "array[].key", and a material's, which depend on its
        !> type, "materials[type=NAME].key" for each type name (aliases included):
        !> "domain.boundaries.xmin.mu", "bodies[].file", "materials[type=drucker_prager].cone".
        !> (A subroutine: gfortran 12 fails on a deferred-length array function result here.)
        module subroutine case_key_paths(paths)
            character(len=:), allocatable, intent(out) :: paths(:)
                !! key paths, in the reader's order, blank-padded to the longest
        end subroutine case_key_paths
    end interface

contains

    !> P-wave speed of a material, sqrt((K + 4G/3)/rho) [m/s]; sqrt(K/rho) for a fluid.
    pure real(wp) function p_wave_speed(mat)
        type(material_spec_type), intent(in) :: mat
            !! material

        real(wp) :: bulk, shear

        if (mat%type == "newtonian") then
            p_wave_speed = sqrt(mat%bulk_modulus/mat%density)
            return
        end if
        bulk = mat%young/(3.0_wp*(1.0_wp - 2.0_wp*mat%poisson))
        shear = mat%young/(2.0_wp*(1.0_wp + mat%poisson))
        p_wave_speed = sqrt((bulk + 4.0_wp*shear/3.0_wp)/mat%density)
    end function p_wave_speed

    !> Stable time step of explicit viscous diffusion, rho dx^2 / (2 dim mu) [s]; huge when
    !> the material has no viscosity.
    pure real(wp) function viscous_time_step(mat, dx, dim)
        type(material_spec_type), intent(in) :: mat
            !! material
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: dim
            !! space dimensions

        if (mat%type == "newtonian" .and. mat%viscosity > 0.0_wp) then
            viscous_time_step = mat%density*dx*dx/(2.0_wp*real(dim, wp)*mat%viscosity)
        else
            viscous_time_step = huge(1.0_wp)
        end if
    end function viscous_time_step

    !> Critical time step of the case at t = 0 [s]: dx / max over bodies (c_p + |v0|), and the
    !> viscous limit of the materials in use.
    pure real(wp) function critical_time_step(case)
        type(case_type), intent(in) :: case
            !! resolved case (materials and bodies set)

        integer :: b
        real(wp) :: speed, viscous

        speed = 0.0_wp
        viscous = huge(1.0_wp)
        do b = 1, size(case%bodies)
            associate (mat => case%materials(case%bodies(b)%material))
                speed = max(speed, p_wave_speed(mat) + norm2(case%bodies(b)%velocity(1:case%dim)))
                viscous = min(viscous, viscous_time_step(mat, case%dx, case%dim))
            end associate
        end do
        if (speed > 0.0_wp) then
            critical_time_step = min(case%dx/speed, viscous)
        else
            critical_time_step = viscous
        end if
    end function critical_time_step

    !> Range of particle sub-cells of a body along each axis (0-based, inclusive).
    !>
    !> Particles sit at the centres of a regular sub-grid of spacing h = dx / ppc:
    !> x_s = origin + (s + 1/2) h, s = 0 .. ncells * ppc - 1. A body holds the particles whose
    !> sub-cell centre lies in [min, max) along every axis. A body holds no particle when
    !> hi(a) < lo(a) for some axis.
    pure subroutine body_subcell_range(case, body, lo, hi)
        type(case_type), intent(in) :: case
            !! resolved case
        type(body_spec_type), intent(in) :: body
            !! the body
        integer, intent(out) :: lo(3)
            !! first sub-cell along each axis (0 for unused axes)
        integer, intent(out) :: hi(3)
            !! last sub-cell along each axis (0 for unused axes)

        integer :: a, nsub
        real(wp) :: h

        lo = 0
        hi = 0
        h = case%dx/real(case%ppc, wp)
        do a = 1, case%dim
            nsub = case%ncells(a)*case%ppc
            lo(a) = max(0, ceiling((body%xmin(a) - case%origin(a))/h - 0.5_wp))
            hi(a) = min(nsub - 1, ceiling((body%xmax(a) - case%origin(a))/h - 0.5_wp) - 1)
        end do
    end subroutine body_subcell_range

end module mpm_case
