!> A small assertion module for the plain test programs under tests/.
!>
!> Each test program creates a `test_suite_type`, calls `check*` for every assertion and
!> ends with `call finish(suite)`, which prints "N passed, N failed" and stops with exit
!> code 1 when anything failed, so CTest reports the suite as failed.
module mpm_testing
    use, intrinsic :: iso_c_binding, only: c_char, c_ptr, c_null_char, c_associated
    use mpm_kinds, only: wp
    implicit none
    private
    public :: test_suite_type, new_suite, check, check_close, check_contains, finish
    public :: temporary_folder

    ! allow(assumed-size, assumed-size-character-intent): a C string passed to libc
    interface
        function c_mkdtemp(template) bind(c, name="mkdtemp") result(path)
            import :: c_char, c_ptr
            character(kind=c_char), intent(inout) :: template(*)
                !! folder name ending in XXXXXX, null-terminated; the Xs are replaced
            type(c_ptr) :: path
        end function c_mkdtemp
    end interface

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

    !> A new, empty folder with a unique name, $TMPDIR/PREFIX_XXXXXX (or under /tmp).
    function temporary_folder(prefix) result(path)
        character(len=*), intent(in) :: prefix
            !! start of the folder's name
        character(len=:), allocatable :: path
            !! the folder created

        character(len=4096) :: base
        character(kind=c_char) :: template(4200)
        character(len=:), allocatable :: name
        integer :: length, stat, i

        call get_environment_variable("TMPDIR", base, length, stat)
        if (stat /= 0 .or. length == 0) base = "/tmp"
        name = trim(base)//"/"//prefix//"_XXXXXX"
        do i = 1, len(name)
            template(i) = name(i:i)
        end do
        template(len(name) + 1) = c_null_char
        if (.not. c_associated(c_mkdtemp(template))) error stop "mkdtemp failed in "//name
        path = ""
        do i = 1, len(name)
            path = path//template(i)
        end do
    end function temporary_folder

end module mpm_testing
