!> A rigid body: `materials[i].type = "rigid"`, key `rho`.
!>
!> The particles of a rigid material form one body that moves as a whole, without
!> deforming: a footing, a pile, a retaining wall, a plate, a boulder. The body translates
!> (no rotation). Along the components a `prescribed_motion` entry names (`"rigid"`: the
!> material's name) it moves at the prescribed velocity, and the force that takes is its
!> reaction; along the others it moves freely under its weight, its loads and the force of
!> the material it touches (mpm_rigid_bodies). Its stress stays zero; it has no elastic
!> energy and limits no time step (its wave speed is taken as zero).
module mpm_material_rigid
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_material, only: material_type, material_key_width, work_stored
    implicit none
    private
    public :: rigid_material_type

    !> A rigid body of density rho.
    type, extends(material_type) :: rigid_material_type
    contains
        procedure, nopass :: names => rigid_names
        procedure, nopass :: keys => rigid_keys
        procedure :: read => rigid_read
        procedure :: wave_speed => rigid_wave_speed
            !! zero: a rigid body carries no wave and limits no time step
        procedure :: summary => rigid_summary
        procedure :: update_stress => rigid_update_stress
            !! the stress stays as it is (zero)
        procedure :: update_stress_block => rigid_update_stress_block
            !! nothing to do for a block
        procedure :: work_kind => rigid_work_kind
            !! stored: there is no work of the stresses to dissipate
        procedure :: rigid => rigid_is_rigid
            !! yes
    end type rigid_material_type

contains

    !> Names accepted for `type`.
    pure subroutine rigid_names(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=material_key_width) :: "rigid"]
    end subroutine rigid_names

    !> Keys of a rigid material.
    pure subroutine rigid_keys(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=material_key_width) :: "name", "type", "rho"]
    end subroutine rigid_keys

    !> A rigid body: `rho` (its mass, with its volume).
    subroutine rigid_read(self, item, error)
        class(rigid_material_type), intent(inout) :: self
            !! the material
        type(cursor_type), intent(in) :: item
            !! the material object ("materials[i]")
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call item%get_real("rho", self%density, error, required=.true., above=0.0_wp, &
            unit="kg/m3")
    end subroutine rigid_read

    !> Zero: a rigid body carries no wave [m/s].
    pure real(wp) function rigid_wave_speed(self)
        class(rigid_material_type), intent(in) :: self
            !! the material

        rigid_wave_speed = 0.0_wp
    end function rigid_wave_speed

    !> "rho = ... kg/m3, one rigid body".
    pure subroutine rigid_summary(self, text)
        class(rigid_material_type), intent(in) :: self
            !! the material
        character(len=:), allocatable, intent(out) :: text
            !! the line

        text = "rho = "//fmt_real(self%density)//" kg/m3; its particles move as one rigid " &
            //"body (translation)"//new_line("a")
    end subroutine rigid_summary

    !> Nothing: the stress of a rigid body stays zero (its particles do not deform).
    pure subroutine rigid_update_stress(self, stress, dstrain, omega, dt, state)
        class(rigid_material_type), intent(in) :: self
        real(wp), intent(inout) :: stress(:)
        real(wp), intent(in) :: dstrain(:)
        real(wp), intent(in) :: omega(3)
        real(wp), intent(in) :: dt
        real(wp), intent(inout) :: state(:)
    end subroutine rigid_update_stress

    !> Nothing, for a block of particles.
    pure subroutine rigid_update_stress_block(self, n, stress, dstrain, omega, dt, state)
        class(rigid_material_type), intent(in) :: self
        integer, intent(in) :: n
        real(wp), intent(inout) :: stress(:, :)
        real(wp), intent(in) :: dstrain(:, :)
        real(wp), intent(in) :: omega(:, :)
        real(wp), intent(in) :: dt
        real(wp), intent(inout) :: state(:, :)
    end subroutine rigid_update_stress_block

    !> Stored: a rigid body does no work of the stresses.
    pure integer function rigid_work_kind(self)
        class(rigid_material_type), intent(in) :: self
            !! the material

        rigid_work_kind = work_stored
    end function rigid_work_kind

    !> A rigid material is rigid.
    pure logical function rigid_is_rigid(self)
        class(rigid_material_type), intent(in) :: self
            !! the material

        rigid_is_rigid = .true.
    end function rigid_is_rigid

end module mpm_material_rigid
