!> What every material model of a case provides (the registry, mpm_case_material_registry,
!> lists them): its names, its keys, how it reads and checks them, its wave speed, its time-step
!> limit and which state it writes. Also the resolved parameters of one material
!> (`material_spec_type`), which the constitutive models of src/material/ are built from.
module mpm_case_material_model
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: material_spec_type, material_model_type, key_width
    public :: cone_plane_strain, cone_compression, cone_extension, cone_names
    public :: softening_none, softening_linear, softening_exponential, softening_names
    public :: degree, read_elasticity, elastic_wave_speed

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

    integer, parameter :: key_width = 14
        !! longest key or model name of a material ("tension_cutoff", "linear_elastic")
    real(wp), parameter :: degree = acos(-1.0_wp)/180.0_wp
        !! one degree [rad]: angles are given in degrees and stored in radians

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

    !> A material model of the case file: one extension per `materials[i].type`, stateless.
    type, abstract :: material_model_type
    contains
        !> Names accepted for `type`; the first is the one stored in material_spec_type%type.
        procedure(list_interface), deferred, nopass :: names
        !> Keys a material of this model may hold ("name" and "type" included).
        procedure(list_interface), deferred, nopass :: keys
        !> Read and check the parameters of a material of this model.
        procedure(read_interface), deferred, nopass :: read
        !> P-wave speed of a material of this model [m/s].
        procedure(speed_interface), deferred, nopass :: wave_speed
        !> Stable time step of a material of this model besides the CFL condition [s].
        procedure, nopass :: time_step_limit => no_time_step_limit
        !> Whether the model writes the plastic strain (its particle state).
        procedure, nopass :: writes_plastic_strain => no_plastic_strain
    end type material_model_type

    abstract interface
        !> A list of names (model names or keys).
        pure subroutine list_interface(list)
            import :: key_width
            character(len=key_width), allocatable, intent(out) :: list(:)
                !! the names
        end subroutine list_interface

        !> Read and check the parameters of one material (its type and name are read).
        subroutine read_interface(item, mat, error)
            import :: cursor_type, material_spec_type, error_type
            type(cursor_type), intent(in) :: item
                !! the material object ("materials[i]")
            type(material_spec_type), intent(inout) :: mat
                !! material being resolved
            type(error_type), allocatable, intent(out) :: error
                !! first error found
        end subroutine read_interface

        !> P-wave speed of a material [m/s].
        pure real(wp) function speed_interface(mat)
            import :: wp, material_spec_type
            type(material_spec_type), intent(in) :: mat
                !! resolved material
        end function speed_interface
    end interface

contains

    !> No time-step limit besides the CFL condition: huge [s].
    pure real(wp) function no_time_step_limit(mat, dx, dim)
        type(material_spec_type), intent(in) :: mat
            !! resolved material
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: dim
            !! space dimensions

        no_time_step_limit = huge(1.0_wp)
    end function no_time_step_limit

    !> No plastic strain.
    pure logical function no_plastic_strain()
        no_plastic_strain = .false.
    end function no_plastic_strain

    !> P-wave speed of an elastic solid, sqrt((K + 4G/3)/rho) [m/s].
    pure real(wp) function elastic_wave_speed(mat)
        type(material_spec_type), intent(in) :: mat
            !! resolved material (E, nu, rho)

        real(wp) :: bulk, shear

        bulk = mat%young/(3.0_wp*(1.0_wp - 2.0_wp*mat%poisson))
        shear = mat%young/(2.0_wp*(1.0_wp + mat%poisson))
        elastic_wave_speed = sqrt((bulk + 4.0_wp*shear/3.0_wp)/mat%density)
    end function elastic_wave_speed

    !> Elastic parameters of a solid: `E`, `nu`, `rho`.
    subroutine read_elasticity(item, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call item%get_real("E", mat%young, error, required=.true., above=0.0_wp, &
            unit="Pa")
        if (allocated(error)) return
        call item%get_real("nu", mat%poisson, error, required=.true., &
            at_least=0.0_wp, below=0.5_wp)
        if (allocated(error)) return
        call item%get_real("rho", mat%density, error, required=.true., &
            above=0.0_wp, unit="kg/m3")
    end subroutine read_elasticity

end module mpm_case_material_model
