!> The abstract material: a constitutive law, everything about it in one extension.
!>
!> A material is one module with an extension of `material_type` (and one line in
!> `mpm_material_registry`): its names for `materials[i].type`, its keys, how it reads and
!> checks them through the case cursor, its wave speed and time-step limit, the state it
!> needs and writes, its lines of the --check summary and its stress update. The case reads
!> it (mpm_case_materials), the solver calls only its bindings. Stress conventions are those
!> of `mpm_stress`.
module mpm_material
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: material_type, material_holder_type, material_key_width, key_path_width
    public :: work_stored, work_plastic, work_viscous, nwork_kinds
    public :: update_each, material_chunk, chunk_in

    integer, parameter :: material_key_width = 14
        !! longest key or type name of a material ("tension_cutoff", "linear_elastic")
    integer, parameter :: key_path_width = 32
        !! longest key path inside a material ("softening.phi_residual")

    integer, parameter :: material_chunk = 32
        !! particles per chunk of the block updates that vectorise across particles
        !! (structure-of-arrays copies of this size on the stack, `chunk_in`)
    integer, parameter :: work_stored = 1, work_plastic = 2, work_viscous = 3
        !! where the work of the stresses goes, beyond the elastic energy the stress stores:
        !! nowhere (an elastic material: every joule is stored), plastic dissipation, viscous
        !! dissipation (`work_kind`)
    integer, parameter :: nwork_kinds = 3
        !! number of work kinds

    !> A constitutive law with its parameters, and how the case file gives them.
    type, abstract :: material_type
        character(len=:), allocatable :: name
            !! name given in the case file
        real(wp) :: density = 0.0_wp
            !! initial mass density [kg/m3]
    contains
        !> Names accepted for `materials[i].type`; the first is the one the case stores.
        procedure(list_interface), deferred, nopass :: names
        !> Keys a material of this type may hold ("name" and "type" included).
        procedure(list_interface), deferred, nopass :: keys
        !> Key paths inside the objects of a material ("softening.type"; default none).
        procedure, nopass :: section_keys => material_section_keys
        !> Read and check the parameters (every key but `name` and `type`), then set up.
        procedure(read_interface), deferred :: read
        !> P-wave speed [m/s].
        procedure(speed_interface), deferred :: wave_speed
        !> P-wave speed at a particle's stress and state [m/s] (default wave_speed()).
        procedure :: wave_speed_at => material_wave_speed_at
        !> Whether the wave speed follows the stress (default no: wave_speed() holds).
        procedure :: speed_varies => material_speed_varies
        !> Stable time step besides the CFL condition [s] (default huge: none).
        procedure :: time_step_limit => material_time_step_limit
        !> Whether the material writes the plastic strain (default no).
        procedure :: writes_plastic_strain => material_writes_plastic_strain
        !> Its lines of the --check summary, after the name and the type.
        procedure(summary_interface), deferred :: summary
        procedure(update_stress_interface), deferred :: update_stress
            !! stress update of one particle over one step
        procedure :: nstate => material_nstate
            !! number of state variables per particle (default 0)
        procedure :: update_stress_block => update_each
            !! update_stress of a block of particles (default: one by one); a material whose
            !! update is a few operations overrides it with a loop over the block
        procedure :: work_kind => material_work_kind
            !! where the work of the stresses goes besides the stored elastic energy
            !! (`work_stored`, `work_plastic`, `work_viscous`; default plastic)
        procedure :: elastic_energy_block => material_elastic_energy_block
            !! stored elastic energy per unit volume of a block of particles (default 0: all
            !! the work of the stresses is dissipated)
        procedure :: at_rest_ratio => material_at_rest_ratio
            !! K0, the ratio of the horizontal to the vertical stress at rest of the geostatic
            !! initial stress (initial_stress.type = "k0") when the case gives none (default
            !! 1: hydrostatic, a fluid)
        procedure :: initial_state => material_initial_state
            !! the state variables of a new particle at its initial position (default: none
            !! set, zero): a strength that varies with depth
        procedure :: needs_initial_state => material_needs_initial_state
            !! whether initial_state gives a particle state a state file does not keep (its
            !! initial position): such a material cannot start from load_state (default no)
        procedure :: reduce_strength => material_reduce_strength
            !! divide the shear strength by a factor (strength reduction, factor of safety):
            !! tan(phi) and c of a frictional material, Su of an undrained one; `reduced`
            !! is false for a material without a strength to reduce (the default)
        procedure :: rigid => material_rigid
            !! whether the particles of the material form one rigid body that moves as a
            !! whole (mpm_material_rigid; default no: a deformable material)
    end type material_type

    !> Holder so that materials of different types fit in one array.
    type :: material_holder_type
        class(material_type), allocatable :: m
            !! the material
    end type material_holder_type

    abstract interface
        !> A list of names (type names or keys).
        pure subroutine list_interface(list)
            import :: material_key_width
            character(len=material_key_width), allocatable, intent(out) :: list(:)
                !! the names
        end subroutine list_interface

        !> Read and check the parameters of a material from its object of the case file.
        subroutine read_interface(self, item, error)
            import :: material_type, cursor_type, error_type
            class(material_type), intent(inout) :: self
                !! the material, its defaults set
            type(cursor_type), intent(in) :: item
                !! the material object ("materials[i]"), its keys checked
            type(error_type), allocatable, intent(out) :: error
                !! first error found
        end subroutine read_interface

        !> P-wave speed of the material [m/s].
        pure real(wp) function speed_interface(self)
            import :: material_type, wp
            class(material_type), intent(in) :: self
                !! the material
        end function speed_interface

        !> Lines of the --check summary: the parameters, each line ending in new_line("a").
        pure subroutine summary_interface(self, text)
            import :: material_type
            class(material_type), intent(in) :: self
                !! the material
            character(len=:), allocatable, intent(out) :: text
                !! the lines
        end subroutine summary_interface

        !> Update the stress of one particle for a strain and a spin increment (objective).
        pure subroutine update_stress_interface(self, stress, dstrain, omega, dt, state)
            import :: material_type, wp
            class(material_type), intent(in) :: self
                !! the material
            real(wp), intent(inout) :: stress(:)
                !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
            real(wp), intent(in) :: dstrain(:)
                !! strain increment D dt, tensor components, same size as stress [-]
            real(wp), intent(in) :: omega(3)
                !! spin increment W dt (xy, yz, zx) [-]
            real(wp), intent(in) :: dt
                !! time step [s] (rate-dependent materials)
            real(wp), intent(inout) :: state(:)
                !! material state of the particle, at least nstate() values (may be larger
                !! when the case mixes materials; use only the first nstate())
        end subroutine update_stress_interface
    end interface

contains

    !> Default: no objects inside a material.
    pure subroutine material_section_keys(list)
        character(len=key_path_width), allocatable, intent(out) :: list(:)
            !! key paths, "section.key"

        allocate (list(0))
    end subroutine material_section_keys

    !> Default: the wave speed of the parameters, whatever the stress.
    pure real(wp) function material_wave_speed_at(self, stress, state)
        class(material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: stress(:)
            !! the particle's stress [Pa]
        real(wp), intent(in) :: state(:)
            !! its state variables

        material_wave_speed_at = self%wave_speed()
    end function material_wave_speed_at

    !> Default: the stiffness does not follow the stress.
    pure logical function material_speed_varies(self)
        class(material_type), intent(in) :: self
            !! the material

        material_speed_varies = .false.
    end function material_speed_varies

    !> Default: no time-step limit besides the CFL condition, huge [s].
    pure real(wp) function material_time_step_limit(self, dx, dim)
        class(material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: dim
            !! space dimensions

        material_time_step_limit = huge(1.0_wp)
    end function material_time_step_limit

    !> Default: no plastic strain.
    pure logical function material_writes_plastic_strain(self)
        class(material_type), intent(in) :: self
            !! the material

        material_writes_plastic_strain = .false.
    end function material_writes_plastic_strain

    !> update_stress of each of n particles, one by one: the default block update, and what
    !> a block update that vectorises does for the cases it does not take.
    pure subroutine update_each(self, n, stress, dstrain, omega, dt, state)
        class(material_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the block
        real(wp), intent(inout) :: stress(:, :)
            !! Cauchy stresses (4 or 6, at least n), tension positive [Pa]
        real(wp), intent(in) :: dstrain(:, :)
            !! strain increments D dt (tensor components, as stress) [-]
        real(wp), intent(in) :: omega(:, :)
            !! spin increments W dt (xy, yz, zx; 3, at least n) [-]
        real(wp), intent(in) :: dt
            !! time step [s]
        real(wp), intent(inout) :: state(:, :)
            !! material states (at least nstate(), at least n)

        integer :: j

        do j = 1, n
            call self%update_stress(stress(:, j), dstrain(:, j), omega(:, j), dt, state(:, j))
        end do
    end subroutine update_each

    !> Particles j0 to j0 + nc - 1 of a block as structures of arrays (particle, component):
    !> the first rows of the stresses and strain increments (4 or 6) and the spins.
    pure subroutine chunk_in(stress, dstrain, omega, j0, nc, t, d, w)
        real(wp), intent(in) :: stress(:, :)
            !! stresses of the block (4 or 6, particles) [Pa]
        real(wp), intent(in) :: dstrain(:, :)
            !! strain increments of the block [-]
        real(wp), intent(in) :: omega(:, :)
            !! spin increments of the block (3, particles) [-]
        integer, intent(in) :: j0, nc
            !! first particle and particles of the chunk (nc <= material_chunk)
        real(wp), intent(inout) :: t(material_chunk, 6), d(material_chunk, 6)
            !! stresses and strain increments of the chunk (rows 1 : nc; columns 1 : 4 in 2D)
        real(wp), intent(inout) :: w(material_chunk, 3)
            !! spin increments of the chunk

        integer :: j, ns

        ns = size(stress, 1)
        do j = 1, nc
            t(j, 1:ns) = stress(1:ns, j0 + j - 1)
            d(j, 1:ns) = dstrain(1:ns, j0 + j - 1)
            w(j, :) = omega(:, j0 + j - 1)
        end do
    end subroutine chunk_in

    !> Default: no state variables.
    pure integer function material_nstate(self)
        class(material_type), intent(in) :: self
            !! the material
        material_nstate = 0
    end function material_nstate

    !> Default K0: 1, the hydrostatic stress of a fluid at rest.
    pure real(wp) function material_at_rest_ratio(self)
        class(material_type), intent(in) :: self
            !! the material
        material_at_rest_ratio = 1.0_wp
    end function material_at_rest_ratio

    !> Default: a new particle's state stays zero.
    pure subroutine material_initial_state(self, x, state)
        class(material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: x(:)
            !! the particle's initial position [m]
        real(wp), intent(inout) :: state(:)
            !! its state variables (zero on entry)
    end subroutine material_initial_state

    !> Default: the state of a particle needs nothing of its creation.
    pure logical function material_needs_initial_state(self)
        class(material_type), intent(in) :: self
            !! the material
        material_needs_initial_state = .false.
    end function material_needs_initial_state

    !> Default: a deformable material.
    pure logical function material_rigid(self)
        class(material_type), intent(in) :: self
            !! the material
        material_rigid = .false.
    end function material_rigid

    !> Default: no strength to reduce (an elastic solid, a fluid); the material is unchanged.
    pure subroutine material_reduce_strength(self, factor, reduced)
        class(material_type), intent(inout) :: self
            !! the material
        real(wp), intent(in) :: factor
            !! strength reduction factor F > 0 [-]
        logical, intent(out) :: reduced
            !! whether the material has a strength that was reduced
        reduced = .false.
    end subroutine material_reduce_strength

    !> Default: the work of the stresses is dissipated (plastic), nothing is stored.
    pure integer function material_work_kind(self)
        class(material_type), intent(in) :: self
            !! the material
        material_work_kind = work_plastic
    end function material_work_kind

    !> Stored elastic energy per unit (current) volume of n particles; default 0.
    pure subroutine material_elastic_energy_block(self, n, stress, state, density)
        class(material_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the block
        real(wp), intent(in) :: stress(:, :)
            !! Cauchy stresses (4 or 6, at least n), tension positive [Pa]
        real(wp), intent(in) :: state(:, :)
            !! material states (at least nstate(), at least n)
        real(wp), intent(out) :: density(:)
            !! stored elastic energy per unit volume (at least n) [J/m3]

        density(1:n) = 0.0_wp
    end subroutine material_elastic_energy_block

end module mpm_material
