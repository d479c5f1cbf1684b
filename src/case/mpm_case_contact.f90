!> The `contact` key of a case: frictional contact with a rigid terrain surface.
module mpm_case_contact
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: contact_section_type, read_contact, contact_keys

    character(len=*), parameter :: contact_keys(*) = [character(len=6) :: "type", "mu", "file", &
        "scale", "offset"]
        !! keys of `contact`

    !> `contact`: the rigid surface the material slides on, if any.
    type :: contact_section_type
        character(len=:), allocatable :: type
            !! "none" or "terrain_stl" (frictional contact with a rigid surface from an STL file)
        real(wp) :: mu = 0.0_wp
            !! Coulomb friction coefficient of the terrain [-]
        character(len=:), allocatable :: file
            !! STL file of the terrain surface (terrain_stl)
        real(wp) :: scale = 1.0_wp
            !! factor on the STL coordinates (units to metres) [-]
        real(wp) :: offset(3) = 0.0_wp
            !! added to the scaled STL coordinates [m]
    end type contact_section_type

contains

    !> `contact`: "none", or "terrain_stl": frictional contact with the rigid surface of an
    !> STL file (mu, file; optional scale and offset of its coordinates).
    subroutine read_contact(root, contact, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(contact_section_type), intent(inout) :: contact
            !! the contact section (type set to "none")
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found, exists
        integer :: k, code

        call root%get_typed("contact", "object", "an object", cur, found, error)
        if (allocated(error) .or. .not. found) return
        call cur%check_keys(contact_keys, error)
        if (allocated(error)) return
        code = 0
        call cur%get_choice("type", [character(len=11) :: "none", "terrain_stl"], [0, 1], code, &
            error)
        if (allocated(error)) return
        if (code == 0) then
            do k = 2, size(contact_keys)
                if (cur%has(trim(contact_keys(k)))) then
                    call cur%fail(error, "contact."//trim(contact_keys(k))// &
                        ' only applies to contact.type = "terrain_stl"; remove it')
                    return
                end if
            end do
            return
        end if
        contact%type = "terrain_stl"
        call cur%get_real("mu", contact%mu, error, required=.true., at_least=0.0_wp)
        if (allocated(error)) return
        call cur%get_path("file", 0, contact%file, error, required=.true.)
        if (allocated(error)) return
        inquire (file=contact%file, exist=exists)
        if (len(contact%file) == 0 .or. .not. exists) then
            call cur%fail(error, "contact.file: STL file '"//contact%file// &
                "' not found (a relative path is taken from the current working directory)")
            return
        end if
        call cur%get_real("scale", contact%scale, error, above=0.0_wp)
        if (allocated(error)) return
        call cur%get_vector("offset", 3, contact%offset, error, unit="m")
    end subroutine read_contact

end module mpm_case_contact
