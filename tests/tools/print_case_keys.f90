!> Print every key path the case reader accepts, one per line (mpm_case::case_key_paths), then
!> the names the registries give the keys that choose an extension, one per line as
!> "=<key path> <name>" (output fields, material types, boundary conditions, shape
!> functions), for tests/schema/check_schema.py, which compares both with
!> docs/case.schema.json.
program print_case_keys
    use mpm_case, only: case_key_paths
    use mpm_case_output_fields, only: output_fields
    use mpm_material_registry, only: material_choices
    use mpm_boundary_registry, only: boundary_choices
    use mpm_shape_factory, only: shape_choices
    implicit none

    character(len=:), allocatable :: paths(:)
    integer :: i

    call case_key_paths(paths)
    do i = 1, size(paths)
        write (*, "(a)") trim(paths(i))
    end do
    call put_choices("output.fields", output_fields%name)
    call put_choices("materials.type", material_choices())
    call put_choices("domain.boundaries.type", boundary_choices())
    call put_choices("solver.shape_function", shape_choices())

contains

    !> The names a key may take.
    subroutine put_choices(path, names)
        character(len=*), intent(in) :: path
            !! the key path
        character(len=*), intent(in) :: names(:)
            !! its names

        integer :: k

        do k = 1, size(names)
            write (*, "(a)") "="//path//" "//trim(names(k))
        end do
    end subroutine put_choices

end program print_case_keys
