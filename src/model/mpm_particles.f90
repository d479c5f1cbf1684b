!> Material points as a structure of arrays.
!>
!> Components come first so the components of one particle are contiguous: `x(dim, n)`.
!> A 2D (plane strain) case stores 2 vector components; stress and strain store the
!> out-of-plane normal component too (4 components in 2D, 6 in 3D), Voigt order
!> xx yy zz xy [yz zx]. Tension is positive. Strain components are tensor components
!> (eps_xy, not the engineering shear gamma_xy = 2 eps_xy).
!>
!> Every per-particle array is listed once, in the field table (`mpm_particle_fields.inc`:
!> the component and its `particle_field_type`). Allocation (`new_particles`), the records
!> that carry particles between images (`pack_particles`, `rebuild_particles`), the byte
!> counts (`particle_bytes`, `created_particle_bytes`) and the state files (`mpm_state`,
!> through `particle_field`, `get_field` and `put_field`) all loop over that table, so a new
!> per-particle array is a component of `particles_type` and one entry of the table.
module mpm_particles
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_other
    implicit none
    private
    public :: particles_type, new_particles, nstress_of, particle_bytes, record_length, &
        pack_particles, rebuild_particles, particle_number
    public :: particle_field_type, particle_field_count, particle_field, field_index, &
        values_per_particle, field_units, field_held, get_field, get_field_integers, &
        put_field, put_field_integers, hold_field, release_field, created_particle_bytes, &
        move_particles
    public :: per_particle, per_axis, per_stress, per_tensor, per_state
    public :: held_always, held_written, held_apic, held_driver, held_images, held_loads, &
        held_water

    ! Values a field keeps per particle
    integer, parameter :: per_particle = 1
        !! one
    integer, parameter :: per_axis = 2
        !! one per axis (dim)
    integer, parameter :: per_stress = 3
        !! one per stored stress component (nstress: 4 in 2D, 6 in 3D)
    integer, parameter :: per_tensor = 4
        !! a dim x dim tensor, stored (dim, dim, n)
    integer, parameter :: per_state = 5
        !! one per material state variable (nstate)

    ! When a field is held (allocated)
    integer, parameter :: held_always = 1
        !! always: new_particles allocates it
    integer, parameter :: held_written = 2
        !! allocated by new_particles; a run keeps it only when the case writes it (an output
        !! field or a state file)
    integer, parameter :: held_apic = 3
        !! with solver.transfer = "apic" (and read from a state file that has it)
    integer, parameter :: held_driver = 4
        !! allocated only by drivers that need it (verification problems)
    integer, parameter :: held_images = 5
        !! when the particles are spread over images
    integer, parameter :: held_loads = 6
        !! when the case has traction or point loads (mpm_loads); not in the byte counts of
        !! created_particle_bytes
    integer, parameter :: held_water = 7
        !! when the case has pore water (mpm_pore_water; the effective stress and the water
        !! velocity only when written); not in the byte counts of created_particle_bytes

    !> What the field table says of one per-particle array.
    type :: particle_field_type
        character(len=12) :: name = ""
            !! component of particles_type; also the dataset name in state files
        integer :: values = per_particle
            !! values per particle: per_particle, per_axis, per_stress, per_tensor or per_state
        character(len=8) :: units = "-"
            !! units (in 3D)
        character(len=8) :: units_2d = ""
            !! units in 2D when they differ (per metre of thickness), else ""
        integer :: held = held_always
            !! when the array is allocated: held_always, held_written, held_apic, held_driver
            !! held_images, held_loads or held_water
        logical :: whole = .false.
            !! integer values (material index, id), else real(wp)
        logical :: saved = .true.
            !! kept by state files
        logical :: voigt = .false.
            !! Voigt stress components (state files name them in a "components" attribute)
        logical :: identity = .false.
            !! starts as the identity tensor, else zero
    end type particle_field_type

    ! What inspect_field and change_field do with a field
    integer, parameter :: job_describe = 1, job_pack = 2, job_copy = 3, job_allocate = 4, &
        job_regrow = 5, job_unpack = 6, job_put = 7, job_release = 8

    !> A read-only job on fields (inspect_field): describe, pack records, copy values.
    type :: inspect_job_type
        integer :: action = job_describe
        logical :: found = .false.
            !! the table has the field asked for
        type(particle_field_type) :: field
            !! its description
        logical :: held = .false.
            !! its array is allocated
        integer, allocatable :: index(:)
            !! job_pack: particles to pack
        integer :: record = 0
            !! job_pack: values per record
        integer :: offset = 0
            !! job_pack: values of the record before this field (advanced past it)
        real(wp), allocatable :: buffer(:)
            !! job_pack: the records
        real(wp), allocatable :: reals(:, :)
            !! job_copy: the values (values per particle, n) of a real field
        integer, allocatable :: integers(:)
            !! job_copy: the values (n) of an integer field
    end type inspect_job_type

    !> A job that changes fields (change_field): allocate, regrow, unpack, put, release.
    type :: change_job_type
        integer :: action = job_allocate
        logical :: found = .false.
            !! the table has the field asked for
        type(particle_field_type) :: field
            !! its description
        integer :: only = 0
            !! for job_allocate, the one field to allocate; 0: every field held_always or
            !! held_written
        integer :: n = 0
            !! job_allocate, job_regrow: particles
        integer :: dim = 2
            !! for job_allocate, the space dimensions
        integer :: nstate = 0
            !! for job_allocate, the material state variables per particle
        integer, allocatable :: kept(:)
            !! job_regrow: particles kept, in their order, at the start of the new arrays
        real(wp), allocatable :: records(:)
            !! job_unpack: records of arriving particles
        integer :: record = 0
            !! job_unpack: values per record
        integer :: offset = 0
            !! job_unpack: values of the record before this field (advanced past it)
        integer :: first = 1
            !! job_unpack: index of the first arriving particle
        real(wp), allocatable :: reals(:, :)
            !! job_put: values of the first rows of a real field (rows, n)
        integer, allocatable :: integers(:)
            !! job_put: values of an integer field (n)
        integer :: stat = 0
            !! stat of a failed allocation
        character(len=256) :: message = ""
            !! errmsg of a failed allocation
    end type change_job_type

    !> One entry of the field table, handed to a job (inspect_field, change_field).
    interface visit
        module procedure inspect_real1, inspect_real2, inspect_real3, inspect_integer1, &
            change_real1, change_real2, change_real3, change_integer1
    end interface visit

    !> All particles of a run.
    type :: particles_type
        integer :: n = 0
            !! number of particles
        integer :: dim = 2
            !! space dimensions
        integer :: nstress = 4
            !! stress/strain components: 4 in 2D (xx yy zz xy), 6 in 3D (xx yy zz xy yz zx)
        real(wp), allocatable :: x(:, :)
            !! position (dim, n) [m]
        real(wp), allocatable :: u(:, :)
            !! displacement since the start of the run (dim, n) [m]; kept only when the case
            !! writes it (output field or state file)
        real(wp), allocatable :: v(:, :)
            !! velocity (dim, n) [m/s]
        real(wp), allocatable :: mass(:)
            !! mass (n) [kg]; per metre of thickness in 2D [kg/m]
        real(wp), allocatable :: volume(:)
            !! current volume (n) [m3]; area in 2D [m2]
        real(wp), allocatable :: volume0(:)
            !! initial volume (n) [m3]; area in 2D [m2]
        real(wp), allocatable :: stress(:, :)
            !! Cauchy stress (nstress, n), tension positive [Pa]
        real(wp), allocatable :: strain(:, :)
            !! accumulated logarithmic-rate strain (nstress, n), tensor components [-]; kept
            !! only when the case writes it (output field or state file)
        real(wp), allocatable :: f(:, :, :)
            !! deformation gradient (dim, dim, n) [-]
        real(wp), allocatable :: lp0(:, :)
            !! initial GIMP half-size of the particle domain (dim, n) [m]
        integer, allocatable :: material(:)
            !! material index into case%materials (n)
        integer :: nstate = 0
            !! material state variables per particle (0 when no material of the case has any)
        real(wp), allocatable :: state(:, :)
            !! material state (nstate, n), e.g. accumulated plastic shear strain [-]
        real(wp), allocatable :: body_force(:, :)
            !! extra body force per unit mass (dim, n), allocated only by drivers that prescribe
            !! one (manufactured solutions); added to gravity in P2G [m/s2]
        real(wp), allocatable :: affine(:, :, :)
            !! APIC affine velocity C_p = sum_i v_i grad(N_i)^T (dim, dim, n) [1/s], allocated
            !! only with solver.transfer = "apic"
        integer, allocatable :: load(:)
            !! the traction or point load the particle carries (index into case%loads, 0 for
            !! none) (n); allocated only when the case has such loads (mpm_loads)
        real(wp), allocatable :: load_share(:)
            !! the particle's share of that load (n): its force is load_share times the
            !! load's vector at its time factor (traction: the loaded area it carries [m2; m in
            !! 2D]; point load: 1)
        real(wp), allocatable :: pore_pressure(:)
            !! pore pressure p of a particle of a saturated soil, compression positive (n)
            !! [Pa]; zero for the dry ones. `stress` is the total stress, sigma' - p I;
            !! allocated only when the case has pore water
        real(wp), allocatable :: effective(:, :)
            !! effective stress sigma' = sigma + p I (nstress, n) [Pa]; only when written
        real(wp), allocatable :: water_v(:, :)
            !! velocity of the pore water v + q / n (dim, n), q Darcy's flux [m/s]; only when
            !! written
        integer, allocatable :: id(:)
            !! index of each particle in the whole run (n), allocated only when the particles
            !! are spread over images (mpm_parallel); otherwise the index is the id
    end type particles_type

contains

    !> Number of stress components stored for a dimension: 4 in 2D, 6 in 3D.
    pure integer function nstress_of(dim)
        integer, intent(in) :: dim
            !! space dimensions
        if (dim == 2) then
            nstress_of = 4
        else
            nstress_of = 6
        end if
    end function nstress_of

    ! ----------------------------------------------------------------------------------------
    ! The field table
    ! ----------------------------------------------------------------------------------------

    !> Field k of the table, read only: its description and what `job` asks of its values.
    pure subroutine inspect_field(particles, k, job)
        type(particles_type), intent(in) :: particles
        integer, intent(in) :: k
        type(inspect_job_type), intent(inout) :: job

        job%found = .true.
        include "mpm_particle_fields.inc"
    end subroutine inspect_field

    !> Field k of the table, changed as `job` asks.
    pure subroutine change_field(particles, k, job)
        type(particles_type), intent(inout) :: particles
        integer, intent(in) :: k
        type(change_job_type), intent(inout) :: job

        job%found = .true.
        include "mpm_particle_fields.inc"
    end subroutine change_field

    !> A description of the field table (only name, values and units are required).
    pure function field(name, values, units, units_2d, held, saved, voigt, identity) &
            result(described)
        character(len=*), intent(in) :: name
        integer, intent(in) :: values
        character(len=*), intent(in) :: units
        character(len=*), intent(in), optional :: units_2d
        integer, intent(in), optional :: held
        logical, intent(in), optional :: saved, voigt, identity
        type(particle_field_type) :: described

        described%name = name
        described%values = values
        described%units = units
        if (present(units_2d)) described%units_2d = units_2d
        if (present(held)) described%held = held
        if (present(saved)) described%saved = saved
        if (present(voigt)) described%voigt = voigt
        if (present(identity)) described%identity = identity
    end function field

    !> Number of fields in the table.
    pure integer function particle_field_count()
        type(particles_type) :: none
        type(inspect_job_type) :: job

        particle_field_count = 0
        do
            call inspect_field(none, particle_field_count + 1, job)
            if (.not. job%found) exit
            particle_field_count = particle_field_count + 1
        end do
    end function particle_field_count

    !> The description of field k of the table (1 .. particle_field_count()).
    pure function particle_field(k) result(described)
        integer, intent(in) :: k
            !! field number
        type(particle_field_type) :: described
            !! its description (name "" when there is no field k)

        type(particles_type) :: none
        type(inspect_job_type) :: job

        call inspect_field(none, k, job)
        described = job%field
        if (.not. job%found) described = particle_field_type()
    end function particle_field

    !> Number in the table of the field called `name` (a component of particles_type), 0 when
    !> there is none.
    pure integer function field_index(name)
        character(len=*), intent(in) :: name
            !! component name, "x", "stress", ...

        type(particle_field_type) :: described
        integer :: k

        do k = 1, particle_field_count()
            described = particle_field(k)
            if (described%name == name) then
                field_index = k
                return
            end if
        end do
        field_index = 0
    end function field_index

    !> Values per particle of a field, for a dimension and a number of state variables.
    pure integer function values_per_particle(described, dim, nstate)
        type(particle_field_type), intent(in) :: described
            !! the field
        integer, intent(in) :: dim
            !! space dimensions
        integer, intent(in) :: nstate
            !! material state variables per particle

        select case (described%values)
        case (per_axis)
            values_per_particle = dim
        case (per_stress)
            values_per_particle = nstress_of(dim)
        case (per_tensor)
            values_per_particle = dim*dim
        case (per_state)
            values_per_particle = nstate
        case default
            values_per_particle = 1
        end select
    end function values_per_particle

    !> Units of a field in a dimension ("kg/m" for a 2D mass).
    pure function field_units(described, dim) result(units)
        type(particle_field_type), intent(in) :: described
            !! the field
        integer, intent(in) :: dim
            !! space dimensions
        character(len=:), allocatable :: units

        if (dim == 2 .and. len_trim(described%units_2d) > 0) then
            units = trim(described%units_2d)
        else
            units = trim(described%units)
        end if
    end function field_units

    !> Whether the array of field k is allocated.
    pure logical function field_held(particles, k)
        type(particles_type), intent(in) :: particles
            !! the particles
        integer, intent(in) :: k
            !! field number

        type(inspect_job_type) :: job

        call inspect_field(particles, k, job)
        field_held = job%held
    end function field_held

    !> A copy of a real field k as (values per particle, n); (0, 0) when it is not held.
    subroutine get_field(particles, k, values)
        type(particles_type), intent(in) :: particles
            !! the particles
        integer, intent(in) :: k
            !! field number (a real field)
        real(wp), allocatable, intent(out) :: values(:, :)
            !! its values

        type(inspect_job_type) :: job

        job%action = job_copy
        call inspect_field(particles, k, job)
        if (allocated(job%reals)) then
            call move_alloc(job%reals, values)
        else
            allocate (values(0, 0))
        end if
    end subroutine get_field

    !> A copy of an integer field k (n); empty when it is not held.
    subroutine get_field_integers(particles, k, values)
        type(particles_type), intent(in) :: particles
            !! the particles
        integer, intent(in) :: k
            !! field number (an integer field)
        integer, allocatable, intent(out) :: values(:)
            !! its values

        type(inspect_job_type) :: job

        job%action = job_copy
        call inspect_field(particles, k, job)
        if (allocated(job%integers)) then
            call move_alloc(job%integers, values)
        else
            allocate (values(0))
        end if
    end subroutine get_field_integers

    !> Set the first rows of a held real field k (all particles): a state file with fewer
    !> state variables than the case fills the first ones.
    subroutine put_field(particles, k, values)
        type(particles_type), intent(inout) :: particles
            !! the particles
        integer, intent(in) :: k
            !! field number (a real field, allocated)
        real(wp), intent(in) :: values(:, :)
            !! values (rows, n), rows at most the field's values per particle

        type(change_job_type) :: job

        job%action = job_put
        job%reals = values
        call change_field(particles, k, job)
    end subroutine put_field

    !> Set a held integer field k.
    subroutine put_field_integers(particles, k, values)
        type(particles_type), intent(inout) :: particles
            !! the particles
        integer, intent(in) :: k
            !! field number (an integer field, allocated)
        integer, intent(in) :: values(:)
            !! values (n)

        type(change_job_type) :: job

        job%action = job_put
        job%integers = values
        call change_field(particles, k, job)
    end subroutine put_field_integers

    !> Allocate field k for the particles (zero, or the identity), whatever its `held`.
    subroutine hold_field(particles, k, error)
        type(particles_type), intent(inout) :: particles
            !! the particles (n, dim and nstate set)
        integer, intent(in) :: k
            !! field number
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        type(change_job_type) :: job

        job%action = job_allocate
        job%only = k
        job%n = particles%n
        job%dim = particles%dim
        job%nstate = particles%nstate
        call change_field(particles, k, job)
        if (job%stat /= 0) then
            call fatal_error(error, "cannot allocate the particles' "// &
                trim(job%field%name)//": "//trim(job%message), exit_other)
        end if
    end subroutine hold_field

    !> Deallocate field k (nothing when it is not held).
    subroutine release_field(particles, k)
        type(particles_type), intent(inout) :: particles
            !! the particles
        integer, intent(in) :: k
            !! field number

        type(change_job_type) :: job

        job%action = job_release
        call change_field(particles, k, job)
    end subroutine release_field

    !> Move every array of `from` into `to` (which loses what it held), one field at a time,
    !> so that memory holds the particles once and one field more.
    subroutine move_particles(from, to, error)
        type(particles_type), intent(inout) :: from
            !! particles to move; left without arrays (n = 0)
        type(particles_type), intent(out) :: to
            !! the particles of `from`
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        real(wp), allocatable :: values(:, :)
        integer, allocatable :: integers(:)
        type(particle_field_type) :: described
        integer :: k

        to%n = from%n
        to%dim = from%dim
        to%nstress = from%nstress
        to%nstate = from%nstate
        do k = 1, particle_field_count()
            if (.not. field_held(from, k)) cycle
            described = particle_field(k)
            if (described%whole) then
                call get_field_integers(from, k, integers)
            else
                call get_field(from, k, values)
            end if
            call release_field(from, k)
            call hold_field(to, k, error)
            if (allocated(error)) return
            if (described%whole) then
                call put_field_integers(to, k, integers)
            else
                call put_field(to, k, values)
            end if
        end do
        from%n = 0
    end subroutine move_particles

    !> Allocate storage for n particles, zeroed (F set to the identity): every field that is
    !> held_always or held_written.
    subroutine new_particles(particles, dim, n, error, nstate)
        type(particles_type), intent(out) :: particles
            !! particles to create
        integer, intent(in) :: dim
            !! space dimensions (2 or 3)
        integer, intent(in) :: n
            !! number of particles
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated
        integer, intent(in), optional :: nstate
            !! material state variables per particle (default 0)

        type(change_job_type) :: job
        integer :: k
        character(len=32) :: buf

        particles%n = n
        particles%dim = dim
        particles%nstress = nstress_of(dim)
        particles%nstate = 0
        if (present(nstate)) particles%nstate = nstate
        job%action = job_allocate
        job%n = n
        job%dim = dim
        job%nstate = particles%nstate
        do k = 1, particle_field_count()
            call change_field(particles, k, job)
            if (job%stat /= 0) then
                write (buf, "(i0)") n
                call fatal_error(error, "cannot allocate "//trim(buf)//" particles: "// &
                    trim(job%message), exit_other)
                return
            end if
        end do
    end subroutine new_particles

    !> The number of particle p for messages: its index in the whole run (its id when the
    !> particles are spread over images).
    pure integer function particle_number(particles, p)
        type(particles_type), intent(in) :: particles
            !! the particles
        integer, intent(in) :: p
            !! index in these particles
        particle_number = p
        if (allocated(particles%id)) particle_number = particles%id(p)
    end function particle_number

    !> Bytes of particle storage per particle (every per-particle array allocated).
    pure integer function particle_bytes(particles)
        type(particles_type), intent(in) :: particles
            !! the particles

        type(inspect_job_type) :: job
        integer :: k

        particle_bytes = 0
        do k = 1, particle_field_count()
            call inspect_field(particles, k, job)
            if (job%held) particle_bytes = particle_bytes + value_bytes(job%field)* &
                values_per_particle(job%field, particles%dim, particles%nstate)
        end do
    end function particle_bytes

    !> Bytes per particle of the particles a case creates (new_particles), with the APIC
    !> affine velocities and the ids of several images when they are held; the fields of
    !> drivers are not counted.
    pure integer function created_particle_bytes(dim, nstate, apic, images)
        integer, intent(in) :: dim
            !! space dimensions
        integer, intent(in) :: nstate
            !! material state variables per particle
        logical, intent(in) :: apic
            !! solver.transfer = "apic"
        logical, intent(in) :: images
            !! the particles are spread over several images

        type(particle_field_type) :: described
        integer :: k

        created_particle_bytes = 0
        do k = 1, particle_field_count()
            described = particle_field(k)
            select case (described%held)
            case (held_always, held_written)
                continue
            case (held_apic)
                if (.not. apic) cycle
            case (held_images)
                if (.not. images) cycle
            case default
                cycle
            end select
            created_particle_bytes = created_particle_bytes + value_bytes(described)* &
                values_per_particle(described, dim, nstate)
        end do
    end function created_particle_bytes

    !> Bytes of one value of a field.
    pure integer function value_bytes(described)
        type(particle_field_type), intent(in) :: described

        if (described%whole) then
            value_bytes = storage_size(1)/8
        else
            value_bytes = storage_size(1.0_wp)/8
        end if
    end function value_bytes

    !> Values in the record of one particle (pack_particles): every array the particles keep.
    pure integer function record_length(particles)
        type(particles_type), intent(in) :: particles
            !! the particles

        type(inspect_job_type) :: job
        integer :: k

        record_length = 0
        do k = 1, particle_field_count()
            call inspect_field(particles, k, job)
            if (job%held) record_length = record_length + &
                values_per_particle(job%field, particles%dim, particles%nstate)
        end do
    end function record_length

    !> The records of the particles where `mask` is true, in index order, one after the
    !> other, each the values of every held field in table order (integers as reals: exact
    !> below 2^53).
    subroutine pack_particles(particles, mask, buf)
        type(particles_type), intent(in) :: particles
            !! the particles
        logical, intent(in) :: mask(:)
            !! particles to pack (n)
        real(wp), allocatable, intent(out) :: buf(:)
            !! records (record_length x count(mask))

        type(inspect_job_type) :: job
        integer :: p, k

        job%action = job_pack
        job%index = pack([(p, p = 1, particles%n)], mask)
        job%record = record_length(particles)
        allocate (job%buffer(job%record*size(job%index)))
        job%offset = 0
        do k = 1, particle_field_count()
            call inspect_field(particles, k, job)
        end do
        call move_alloc(job%buffer, buf)
    end subroutine pack_particles

    !> Keep the particles where `keep` is true (in their order) and append the particles of
    !> `records` (pack_particles of particles with the same arrays).
    subroutine rebuild_particles(particles, keep, records, error)
        type(particles_type), intent(inout) :: particles
            !! the particles
        logical, intent(in) :: keep(:)
            !! particles that stay (n)
        real(wp), intent(in) :: records(:)
            !! records of the arriving particles
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        type(change_job_type) :: job
        integer :: p, k, nfields

        nfields = particle_field_count()
        job%action = job_regrow
        job%kept = pack([(p, p = 1, particles%n)], keep)
        job%record = record_length(particles)
        job%n = size(job%kept) + size(records)/job%record
        do k = 1, nfields
            call change_field(particles, k, job)
            if (job%stat /= 0) then
                call fatal_error(error, "cannot allocate the particles of this image after "// &
                    "the exchange with its neighbours: "//trim(job%message), exit_other)
                return
            end if
        end do
        particles%n = job%n
        job%action = job_unpack
        job%records = records
        job%first = size(job%kept) + 1
        job%offset = 0
        do k = 1, nfields
            call change_field(particles, k, job)
        end do
    end subroutine rebuild_particles

    ! ----------------------------------------------------------------------------------------
    ! Jobs on one field, by the rank and type of its array
    ! ----------------------------------------------------------------------------------------

    pure subroutine inspect_real1(job, a, described)
        type(inspect_job_type), intent(inout) :: job
        real(wp), allocatable, intent(in) :: a(:)
        type(particle_field_type), intent(in) :: described

        job%field = described
        job%held = allocated(a)
        if (job%held) call inspect_reals(job, a, 1, size(a))
    end subroutine inspect_real1

    pure subroutine inspect_real2(job, a, described)
        type(inspect_job_type), intent(inout) :: job
        real(wp), allocatable, intent(in) :: a(:, :)
        type(particle_field_type), intent(in) :: described

        job%field = described
        job%held = allocated(a)
        if (job%held) call inspect_reals(job, a, size(a, 1), size(a, 2))
    end subroutine inspect_real2

    pure subroutine inspect_real3(job, a, described)
        type(inspect_job_type), intent(inout) :: job
        real(wp), allocatable, intent(in) :: a(:, :, :)
        type(particle_field_type), intent(in) :: described

        job%field = described
        job%held = allocated(a)
        if (job%held) call inspect_reals(job, a, size(a, 1)*size(a, 2), size(a, 3))
    end subroutine inspect_real3

    pure subroutine inspect_integer1(job, a, described)
        type(inspect_job_type), intent(inout) :: job
        integer, allocatable, intent(in) :: a(:)
        type(particle_field_type), intent(in) :: described

        job%field = described
        job%field%whole = .true.
        job%held = allocated(a)
        if (.not. job%held) return
        select case (job%action)
        case (job_pack)
            job%buffer(job%offset + 1::job%record) = real(a(job%index), wp)
            job%offset = job%offset + 1
        case (job_copy)
            job%integers = a
        case default
            continue
        end select
    end subroutine inspect_integer1

    !> A read-only job on the values (m, n) of a real field (any rank, by sequence association).
    pure subroutine inspect_reals(job, a, m, n)
        type(inspect_job_type), intent(inout) :: job
        integer, intent(in) :: m, n
        real(wp), intent(in) :: a(m, n)

        integer :: j, at

        select case (job%action)
        case (job_pack)
            do j = 1, size(job%index)
                at = (j - 1)*job%record + job%offset
                job%buffer(at + 1:at + m) = a(:, job%index(j))
            end do
            job%offset = job%offset + m
        case (job_copy)
            job%reals = a
        case default
            continue
        end select
    end subroutine inspect_reals

    pure subroutine change_real1(job, a, described)
        type(change_job_type), intent(inout) :: job
        real(wp), allocatable, intent(inout) :: a(:)
        type(particle_field_type), intent(in) :: described

        real(wp), allocatable :: b(:)
        integer :: stat
        character(len=256) :: message

        job%field = described
        select case (job%action)
        case (job_allocate)
            if (.not. allocating(job)) return
            allocate (a(job%n), stat=stat, errmsg=message)
            call note_failure(job, stat, message)
            if (stat /= 0) return
            a = 0.0_wp
        case (job_release)
            if (allocated(a)) deallocate (a)
        case (job_regrow)
            if (.not. allocated(a)) return
            allocate (b(job%n), stat=stat, errmsg=message)
            call note_failure(job, stat, message)
            if (stat /= 0) return
            call keep_reals(a, 1, size(a), b, job%n, job%kept)
            call move_alloc(b, a)
        case default
            if (allocated(a)) call change_reals(job, a, 1, size(a))
        end select
    end subroutine change_real1

    pure subroutine change_real2(job, a, described)
        type(change_job_type), intent(inout) :: job
        real(wp), allocatable, intent(inout) :: a(:, :)
        type(particle_field_type), intent(in) :: described

        real(wp), allocatable :: b(:, :)
        integer :: stat
        character(len=256) :: message

        job%field = described
        select case (job%action)
        case (job_allocate)
            if (.not. allocating(job)) return
            allocate (a(values_per_particle(described, job%dim, job%nstate), job%n), &
                stat=stat, errmsg=message)
            call note_failure(job, stat, message)
            if (stat /= 0) return
            a = 0.0_wp
        case (job_release)
            if (allocated(a)) deallocate (a)
        case (job_regrow)
            if (.not. allocated(a)) return
            allocate (b(size(a, 1), job%n), stat=stat, errmsg=message)
            call note_failure(job, stat, message)
            if (stat /= 0) return
            call keep_reals(a, size(a, 1), size(a, 2), b, job%n, job%kept)
            call move_alloc(b, a)
        case default
            if (allocated(a)) call change_reals(job, a, size(a, 1), size(a, 2))
        end select
    end subroutine change_real2

    pure subroutine change_real3(job, a, described)
        type(change_job_type), intent(inout) :: job
        real(wp), allocatable, intent(inout) :: a(:, :, :)
        type(particle_field_type), intent(in) :: described

        real(wp), allocatable :: b(:, :, :)
        integer :: stat
        character(len=256) :: message
        integer :: d

        job%field = described
        select case (job%action)
        case (job_allocate)
            if (.not. allocating(job)) return
            allocate (a(job%dim, job%dim, job%n), stat=stat, errmsg=message)
            call note_failure(job, stat, message)
            if (stat /= 0) return
            a = 0.0_wp
            if (described%identity) then
                do d = 1, job%dim
                    a(d, d, :) = 1.0_wp
                end do
            end if
        case (job_release)
            if (allocated(a)) deallocate (a)
        case (job_regrow)
            if (.not. allocated(a)) return
            allocate (b(size(a, 1), size(a, 2), job%n), stat=stat, errmsg=message)
            call note_failure(job, stat, message)
            if (stat /= 0) return
            call keep_reals(a, size(a, 1)*size(a, 2), size(a, 3), b, job%n, job%kept)
            call move_alloc(b, a)
        case default
            if (allocated(a)) call change_reals(job, a, size(a, 1)*size(a, 2), size(a, 3))
        end select
    end subroutine change_real3

    pure subroutine change_integer1(job, a, described)
        type(change_job_type), intent(inout) :: job
        integer, allocatable, intent(inout) :: a(:)
        type(particle_field_type), intent(in) :: described

        integer, allocatable :: b(:)
        integer :: stat
        character(len=256) :: message
        integer :: q

        job%field = described
        job%field%whole = .true.
        select case (job%action)
        case (job_allocate)
            if (.not. allocating(job)) return
            allocate (a(job%n), stat=stat, errmsg=message)
            call note_failure(job, stat, message)
            if (stat /= 0) return
            a = 0
        case (job_release)
            if (allocated(a)) deallocate (a)
        case (job_regrow)
            if (.not. allocated(a)) return
            allocate (b(job%n), stat=stat, errmsg=message)
            call note_failure(job, stat, message)
            if (stat /= 0) return
            b(1:size(job%kept)) = a(job%kept)
            call move_alloc(b, a)
        case (job_unpack)
            if (.not. allocated(a)) return
            do q = job%first, size(a)
                a(q) = nint(job%records((q - job%first)*job%record + job%offset + 1))
            end do
            job%offset = job%offset + 1
        case (job_put)
            if (allocated(a)) a = job%integers
        case default
            continue
        end select
    end subroutine change_integer1

    !> Whether an allocation job allocates this field.
    pure logical function allocating(job)
        type(change_job_type), intent(in) :: job

        if (job%only > 0) then
            allocating = .true.
        else
            allocating = job%field%held == held_always .or. job%field%held == held_written
        end if
    end function allocating

    !> A failed allocation (stat /= 0): the job keeps its stat and message.
    pure subroutine note_failure(job, stat, message)
        type(change_job_type), intent(inout) :: job
        integer, intent(in) :: stat
        character(len=*), intent(in) :: message

        if (stat /= 0) then
            job%stat = stat
            job%message = message
        end if
    end subroutine note_failure

    !> The kept particles' values at the start of the new array.
    pure subroutine keep_reals(a, m, n, b, nb, kept)
        integer, intent(in) :: m, n, nb
        real(wp), intent(in) :: a(m, n)
        real(wp), intent(inout) :: b(m, nb)
        integer, intent(in) :: kept(:)

        b(:, 1:size(kept)) = a(:, kept)
    end subroutine keep_reals

    !> A job that changes the values (m, n) of a real field (any rank, by sequence association).
    pure subroutine change_reals(job, a, m, n)
        type(change_job_type), intent(inout) :: job
        integer, intent(in) :: m, n
        real(wp), intent(inout) :: a(m, n)

        integer :: q, at

        select case (job%action)
        case (job_unpack)
            do q = job%first, n
                at = (q - job%first)*job%record + job%offset
                a(:, q) = job%records(at + 1:at + m)
            end do
            job%offset = job%offset + m
        case (job_put)
            a(1:size(job%reals, 1), :) = job%reals
        case default
            continue
        end select
    end subroutine change_reals

end module mpm_particles
