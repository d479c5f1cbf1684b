!> Fuzz harness of the case reader (make fuzz, tests/fuzz/run_fuzz.sh): reads the case file
!> named on the command line as `mpm_geo --check` does, and throws the result away.
!>
!> Any error is a correct answer to a bad input, so the program always ends with status 0.
!> What must never happen is a crash, a failed runtime check, a trapped floating-point
!> exception or a hang; in the fuzz build the first three end in a signal (fuzz_exit_abort.c
!> turns the exit status of a failed check into SIGABRT) and the fuzzer records the input.
program fuzz_case_reader
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_file, case_summary
    implicit none

    type(case_type) :: case
    type(error_type), allocatable :: error
    character(len=:), allocatable :: path, summary
    integer :: length

    if (command_argument_count() /= 1) then
        write (*, "(a)") "usage: fuzz_case_reader case.json"
        stop
    end if
    call get_command_argument(1, length=length)
    allocate (character(len=length) :: path)
    call get_command_argument(1, path)
    call read_case_file(path, case, error)
    ! a valid case is also summarised, as mpm_geo --check does
    if (.not. allocated(error)) summary = case_summary(case)
end program fuzz_case_reader
