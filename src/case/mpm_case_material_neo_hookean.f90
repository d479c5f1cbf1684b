!> `materials[i].type = "neo_hookean"`: a hyperelastic solid (same parameters as an elastic one).
module mpm_case_material_neo_hookean
    use mpm_case_material_model, only: material_model_type, key_width, read_elasticity, &
        elastic_wave_speed
    implicit none
    private
    public :: neo_hookean_model_type

    !> The model's names, keys and reader.
    type, extends(material_model_type) :: neo_hookean_model_type
    contains
        procedure, nopass :: names => model_names
        procedure, nopass :: keys => model_keys
        procedure, nopass :: read => read_elasticity
        procedure, nopass :: wave_speed => elastic_wave_speed
    end type neo_hookean_model_type

contains

    !> Names accepted for `type`.
    pure subroutine model_names(list)
        character(len=key_width), allocatable, intent(out) :: list(:)
            !! the names, the stored one first

        list = [character(len=key_width) :: "neo_hookean"]
    end subroutine model_names

    !> Keys of a material of this model.
    pure subroutine model_keys(list)
        character(len=key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=key_width) :: "name", "type", "E", "nu", "rho"]
    end subroutine model_keys

end module mpm_case_material_neo_hookean
