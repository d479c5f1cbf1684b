!> A small assertion module for the plain test programs under tests/.
!>
!> Each test program creates a `test_suite_type`, calls `check*` for every assertion and
!> ends with `call finish(suite)`, which prints "N passed, N failed" and stops with exit
!> code 1 when anything failed, so CTest reports the suite as failed.
module mpm_testing
    use mpm_kinds, only: wp
    implicit none
    private
    public :: test_suite_type, new_suite, check, check_close, check_contains, finish

    !> Counters of one test program.
    type :: test_suite_type
        character(len=:), allocatable :: name
            !! suite name, printed with each failure
        integer :: passed = 0
            !! assertions that held
        integer :: failed = 0
            !! assertions that failed
    end type test_suite_type

contains

    !> Start a suite.
    subroutine new_suite(suite, name)
        type(test_suite_type), intent(out) :: suite
        character(len=*), intent(in) :: name
        suite%name = name
        write (*, "(a)") "suite "//name
    end subroutine new_suite

    !> Assert that a condition holds.
    subroutine check(suite, condition, what)
        type(test_suite_type), intent(inout) :: suite
        logical, intent(in) :: condition
            !! the property that must hold
        character(len=*), intent(in) :: what
            !! description printed on failure
        if (condition) then
            suite%passed = suite%passed + 1
        else
            suite%failed = suite%failed + 1
            write (*, "(a)") "FAIL ["//suite%name//"] "//what
        end if
    end subroutine check

    !> Assert |actual - expected| <= tol (absolute) and print both numbers on failure.
    subroutine check_close(suite, actual, expected, tol, what)
        type(test_suite_type), intent(inout) :: suite
        real(wp), intent(in) :: actual
            !! computed value
        real(wp), intent(in) :: expected
            !! reference value
        real(wp), intent(in) :: tol
            !! allowed absolute difference
        character(len=*), intent(in) :: what
            !! description printed on failure

        character(len=200) :: buf

        if (abs(actual - expected) <= tol) then
            suite%passed = suite%passed + 1
        else
            suite%failed = suite%failed + 1
            write (buf, "(3(a,es22.14))") "actual ", actual, " expected ", expected, " tol ", tol
            write (*, "(a)") "FAIL ["//suite%name//"] "//what//": "//trim(buf)
        end if
    end subroutine check_close

    !> Assert that `text` contains `part`.
    subroutine check_contains(suite, text, part, what)
        type(test_suite_type), intent(inout) :: suite
        character(len=*), intent(in) :: text
            !! text to search (a message, say)
        character(len=*), intent(in) :: part
            !! substring that must occur
        character(len=*), intent(in) :: what
            !! description printed on failure
        if (index(text, part) > 0) then
            suite%passed = suite%passed + 1
        else
            suite%failed = suite%failed + 1
            write (*, "(a)") "FAIL ["//suite%name//"] "//what//": '"//part//"' not in '" &
                //text//"'"
        end if
    end subroutine check_contains

    !> Print the totals and stop with exit code 1 when any assertion failed.
    subroutine finish(suite)
        type(test_suite_type), intent(in) :: suite
        write (*, "(i0,a,i0,a)") suite%passed, " passed, ", suite%failed, " failed"
        if (suite%failed > 0) error stop 1
        if (suite%passed == 0) error stop "no assertion was run"
    end subroutine finish

end module mpm_testing
