!> The particle output fields: the registry of what `output.fields` may name and how each
!> is written. A new output field is one entry of `output_fields` (and, when its values are
!> new, a per-particle array of the field table of mpm_particles); the case reads the names
!> from it, mpm_output writes the datasets, the `/xdmf` views and the XDMF attributes from it,
!> and the run keeps an array that only output asks for (`held_written`) when an entry that
!> shows it is listed.
!>
!> Plain data below the case: a field names its source by the name of the particle field
!> table, so the case knows no model.
module mpm_case_output_fields
    implicit none
    private
    public :: output_field_type, output_fields, nfields, field_position, output_field_index
    public :: layout_vector, layout_voigt, layout_scalar

    ! How an output field is stored
    integer, parameter :: layout_vector = 1
        !! a vector per particle, written (n, 3) with z = 0 in 2D; an XDMF Vector
    integer, parameter :: layout_voigt = 2
        !! Voigt components per particle (n, nstress), with a `components` attribute; an XDMF
        !! Matrix and one Scalar per component (views `/xdmf/<name>_xx`, ...)
    integer, parameter :: layout_scalar = 3
        !! one value per particle (n); an XDMF Scalar (Int for an integer field)

    !> One particle output field.
    type :: output_field_type
        character(len=14) :: name = ""
            !! its name in `output.fields`, the dataset of /particles and the XDMF attribute
        character(len=12) :: source = ""
            !! the particle field it shows (a name of the field table of mpm_particles, which
            !! gives its units and whether its values are integers)
        integer :: row = 0
            !! which values of the source: every one for 0, its row r only (a scalar) for
            !! r > 0 (no dataset when the source has fewer rows)
        integer :: layout = layout_scalar
            !! layout_vector, layout_voigt or layout_scalar
        logical :: geometry = .false.
            !! the positions: always written, as the XDMF geometry, not as an attribute
        logical :: plastic = .false.
            !! written only when a material of the case writes the plastic strain
        logical :: water = .false.
            !! written only when the case has pore water (`pore_water`)
    end type output_field_type

    !> The fields in the order of the files, the index and the `--check` line; the names are
    !> at most 14 characters and lower case (the case file may use any letter case).
    type(output_field_type), parameter :: output_fields(*) = [ &
        output_field_type("position", "x", 0, layout_vector, geometry=.true.), &
        output_field_type("displacement", "u", 0, layout_vector), &
        output_field_type("velocity", "v", 0, layout_vector), &
        output_field_type("stress", "stress", 0, layout_voigt), &
        output_field_type("strain", "strain", 0, layout_voigt), &
        output_field_type("material", "material", 0, layout_scalar), &
        output_field_type("mass", "mass", 0, layout_scalar), &
        output_field_type("volume", "volume", 0, layout_scalar), &
        output_field_type("plastic_strain", "state", 1, layout_scalar, plastic=.true.), &
        output_field_type("pore_pressure", "pore_p", 0, layout_scalar, water=.true.), &
        output_field_type("eff_stress", "effective", 0, layout_voigt, water=.true.), &
        output_field_type("water_velocity", "water_v", 0, layout_vector, water=.true.)]

    integer, parameter :: nfields = size(output_fields)
        !! number of output fields
    integer, parameter :: field_position = 1
        !! the positions, always written

contains

    !> Index in `output_fields` of the field called `name` (exact, lower case), 0 if none.
    pure integer function output_field_index(name) result(k)
        character(len=*), intent(in) :: name
            !! a field name

        do k = 1, nfields
            if (trim(output_fields(k)%name) == name) return
        end do
        k = 0
    end function output_field_index

end module mpm_case_output_fields
