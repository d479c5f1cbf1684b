!> `materials[i].type = "newtonian"`: a weakly compressible Newtonian fluid.
module mpm_case_material_newtonian
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    use mpm_case_material_model, only: material_model_type, material_spec_type, key_width
    implicit none
    private
    public :: newtonian_model_type

    !> The model's names, keys and reader.
    type, extends(material_model_type) :: newtonian_model_type
    contains
        procedure, nopass :: names => model_names
        procedure, nopass :: keys => model_keys
        procedure, nopass :: read => model_read
        procedure, nopass :: wave_speed => fluid_wave_speed
        procedure, nopass :: time_step_limit => viscous_limit
    end type newtonian_model_type

contains

    !> Names accepted for `type`.
    pure subroutine model_names(list)
        character(len=key_width), allocatable, intent(out) :: list(:)
            !! the names, the stored one first

        list = [character(len=key_width) :: "newtonian"]
    end subroutine model_names

    !> Keys of a material of this model.
    pure subroutine model_keys(list)
        character(len=key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=key_width) :: "name", "type", "rho", "viscosity", "bulk_modulus"]
    end subroutine model_keys

    !> A Newtonian fluid: `rho`, `viscosity`, `bulk_modulus`.
    subroutine model_read(item, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object ("materials[i]")
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call item%get_real("rho", mat%density, error, required=.true., above=0.0_wp, &
            unit="kg/m3")
        if (allocated(error)) return
        call item%get_real("viscosity", mat%viscosity, error, required=.true., &
            at_least=0.0_wp, unit="Pa s")
        if (allocated(error)) return
        call item%get_real("bulk_modulus", mat%bulk_modulus, error, required=.true., &
            above=0.0_wp, unit="Pa")
    end subroutine model_read

    !> P-wave speed of the fluid, sqrt(K/rho) [m/s].
    pure real(wp) function fluid_wave_speed(mat)
        type(material_spec_type), intent(in) :: mat
            !! resolved material

        fluid_wave_speed = sqrt(mat%bulk_modulus/mat%density)
    end function fluid_wave_speed

    !> Stable time step of explicit viscous diffusion, rho dx^2 / (2 dim mu) [s]; huge
    !> without viscosity.
    pure real(wp) function viscous_limit(mat, dx, dim)
        type(material_spec_type), intent(in) :: mat
            !! resolved material
        real(wp), intent(in) :: dx
            !! cell size [m]
        integer, intent(in) :: dim
            !! space dimensions

        if (mat%viscosity > 0.0_wp) then
            viscous_limit = mat%density*dx*dx/(2.0_wp*real(dim, wp)*mat%viscosity)
        else
            viscous_limit = huge(1.0_wp)
        end if
    end function viscous_limit

end module mpm_case_material_newtonian
