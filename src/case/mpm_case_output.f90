!> The `output` key of a case: folder, intervals and fields of the particle output.
module mpm_case_output
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: lower, quoted_list, same
    use mpm_case_cursor, only: cursor_type, room_folder
    use mpm_case_output_fields, only: output_fields, nfields, field_position
    implicit none
    private
    public :: output_section_type, read_output, output_keys

    character(len=*), parameter :: output_keys(*) = [character(len=16) :: "interval", "fields", &
        "grid", "directory", "overwrite", "history_interval"]
        !! keys of `output`

    !> `output`: what the run writes, where and how often.
    type :: output_section_type
        character(len=:), allocatable :: directory
            !! output folder (default: outputs/<name>)
        real(wp) :: interval = 0.0_wp
            !! time between particle outputs [s]; 0 for no intermediate output
        logical :: fields(nfields) = .true.
            !! which particle fields are written (the entries of mpm_case_output_fields)
        logical :: grid = .false.
            !! also write the grid nodes (mass, velocity, the force of the constraints)
        logical :: overwrite = .false.
            !! allow writing into an existing output folder
        real(wp) :: history_interval = 0.0_wp
            !! time between lines of the energy history [s]; 0: every output step
    end type output_section_type

contains

    !> `output`: folder, intervals and fields.
    subroutine read_output(root, name, tend, output, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        character(len=*), intent(in) :: name
            !! case name (default folder outputs/<name>)
        real(wp), intent(in) :: tend
            !! end time (default interval tend / 20) [s]
        type(output_section_type), intent(inout) :: output
            !! the output section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found

        output%interval = tend/20.0_wp
        output%directory = "outputs/"//name
        output%history_interval = output%interval/10.0_wp
        call root%get_section("output", output_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_real("interval", output%interval, error, at_least=0.0_wp, unit="s")
        if (allocated(error)) return
        output%history_interval = output%interval/10.0_wp
        call read_fields(cur, output%fields, error)
        if (allocated(error)) return
        call cur%get_bool("grid", output%grid, error)
        if (allocated(error)) return
        call cur%get_path("directory", room_folder, output%directory, error)
        if (allocated(error)) return
        call cur%get_bool("overwrite", output%overwrite, error)
        if (allocated(error)) return
        call cur%get_real("history_interval", output%history_interval, error, at_least=0.0_wp, &
            unit="s")
    end subroutine read_output

    !> `output.fields`: unique field names; the position is always written.
    subroutine read_fields(cur, fields, error)
        type(cursor_type), intent(in) :: cur
            !! the output object
        logical, intent(inout) :: fields(nfields)
            !! which fields are written
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=*), parameter :: expect = "an array of field names"
        type(cursor_type) :: list, item
        logical :: found
        integer :: i, f

        call cur%get_typed("fields", "array", expect, list, found, error)
        if (allocated(error) .or. .not. found) return
        fields = .false.
        do i = 1, list%size()
            item = list%item(i)
            call item%check_type("string", "a field name", error)
            if (allocated(error)) return
            do f = 1, nfields
                if (same(lower(item%text()), trim(output_fields(f)%name))) exit
            end do
            if (f > nfields) then
                call item%fail(error, item%path//' = "'//item%text()//'" is not a ' &
                    //"field: must be one of "//quoted_list(output_fields%name))
                return
            end if
            if (fields(f)) then
                call item%fail(error, item%path//' = "'//item%text()//'" is listed ' &
                    //"twice; give each field once")
                return
            end if
            fields(f) = .true.
        end do
        fields(field_position) = .true.
    end subroutine read_fields

end module mpm_case_output
