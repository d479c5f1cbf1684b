!> Print every key path the case reader accepts, one per line (mpm_case::case_key_paths), for
!> tests/schema/check_schema.py, which compares them with docs/case.schema.json.
program print_case_keys
    use mpm_case, only: case_key_paths
    implicit none

    character(len=:), allocatable :: paths(:)
    integer :: i

    call case_key_paths(paths)
    do i = 1, size(paths)
        write (*, "(a)") trim(paths(i))
    end do
end program print_case_keys
