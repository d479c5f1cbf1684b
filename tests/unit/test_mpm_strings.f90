!> The number parser of mpm_strings (parse_real): numbers of the fast path and of strtod both
!> equal to what a Fortran read of the same text gives (correctly rounded), the Fortran "d"
!> exponent, NaN and infinity, exponents out of range and text that is not a number.
program test_mpm_strings
    use mpm_kinds, only: wp, i8
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_strings, only: parse_real, number_invalid, number_finite, number_not_finite, &
        number_too_large
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_strings")
    call test_as_fortran_reads()
    call test_kinds()
    call finish(suite)

contains

    !> parse_real gives the bits of a Fortran list-directed read (gfortran rounds correctly).
    subroutine test_as_fortran_reads()
        character(len=32), parameter :: texts(*) = [character(len=32) :: "0", "-0.0", "1", &
            "+2.5", "0.1", "-123.456e-7", "1.5d3", "6.02214076E23", "1e22", "1e23", &
            "1.7976931348623157e299", "2.2250738585072014e-308", "4.9e-324", &
            "0.30000000000000004", "123456789012345678", "3.14159265358979323846", &
            "1.", ".5", "-.25e+2", "0.000001", "9007199254740993"]
        character(len=32) :: text
        real(wp) :: value, expected
        integer :: i, kind, stat

        do i = 1, size(texts)
            call parse_real(trim(texts(i)), kind, value)
            text = texts(i)
            read (text, *, iostat=stat) expected
            call check(suite, stat == 0, "Fortran reads "//trim(texts(i)))
            call check(suite, kind == number_finite, trim(texts(i))//" is a finite number")
            call check(suite, transfer(value, 1_i8) == transfer(expected, 1_i8), &
                trim(texts(i))//": the bits of a Fortran read")
        end do
    end subroutine test_as_fortran_reads

    subroutine test_kinds()
        real(wp) :: value
        integer :: kind

        call parse_real("nan", kind, value)
        call check(suite, kind == number_not_finite .and. value == 0.0_wp, "nan: not finite, 0")
        call parse_real("-Infinity", kind, value)
        call check(suite, kind == number_not_finite, "-Infinity: not finite")
        call parse_real("1e301", kind, value)
        call check(suite, kind == number_too_large, "1e301: out of range")
        call parse_real("0.001e302", kind, value)
        call check(suite, kind == number_finite .and. value == 1.0e299_wp, &
            "0.001e302 = 1e299 is in range")
        call parse_real("1e", kind, value)
        call check(suite, kind == number_invalid, "1e: no exponent digits")
        call parse_real("1.2.3", kind, value)
        call check(suite, kind == number_invalid, "1.2.3: two points")
        call parse_real("abc", kind, value)
        call check(suite, kind == number_invalid, "abc: not a number")
        call parse_real("", kind, value)
        call check(suite, kind == number_invalid, "empty text")
        call parse_real("-", kind, value)
        call check(suite, kind == number_invalid, "a sign alone")
        call parse_real("1e5x", kind, value)
        call check(suite, kind == number_invalid, "1e5x: text after the number")
    end subroutine test_kinds

end program test_mpm_strings
