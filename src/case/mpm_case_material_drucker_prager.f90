!> `materials[i].type = "drucker_prager"`: an elasto-plastic solid with a Drucker-Prager cone matched to
!> the Mohr-Coulomb parameters.
module mpm_case_material_drucker_prager
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    use mpm_case_material_model, only: material_model_type, material_spec_type, key_width, &
        read_elasticity, elastic_wave_speed, cone_plane_strain, cone_compression, &
        cone_extension, cone_names
    use mpm_case_material_strength, only: read_strength, strength_keys
    implicit none
    private
    public :: drucker_prager_model_type

    !> The model's names, keys and reader.
    type, extends(material_model_type) :: drucker_prager_model_type
    contains
        procedure, nopass :: names => model_names
        procedure, nopass :: keys => model_keys
        procedure, nopass :: read => model_read
        procedure, nopass :: wave_speed => elastic_wave_speed
        procedure, nopass :: writes_plastic_strain => plastic_strain
    end type drucker_prager_model_type

contains

    !> Names accepted for `type`.
    pure subroutine model_names(list)
        character(len=key_width), allocatable, intent(out) :: list(:)
            !! the names, the stored one first

        list = [character(len=key_width) :: "drucker_prager"]
    end subroutine model_names

    !> Keys of a material of this model.
    pure subroutine model_keys(list)
        character(len=key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=key_width) :: "name", "type", "E", "nu", "rho", strength_keys, "cone"]
    end subroutine model_keys

    !> Elasticity (`E`, `nu`, `rho`), strength (mpm_case_material_strength), then `cone`.
    subroutine model_read(item, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object ("materials[i]")
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call read_elasticity(item, mat, error)
        if (allocated(error)) return
        call read_strength(item, "Drucker-Prager", mat, error)
        if (allocated(error)) return
        call item%get_choice("cone", cone_names, [cone_plane_strain, cone_compression, &
            cone_extension], mat%cone, error)
    end subroutine model_read

    !> The plastic shear strain is the state this model writes.
    pure logical function plastic_strain()
        plastic_strain = .true.
    end function plastic_strain

end module mpm_case_material_drucker_prager
