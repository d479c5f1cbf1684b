!> Small text helpers for messages.
module mpm_strings
    use mpm_kinds, only: wp, i8
    implicit none
    private
    public :: vector_text, int_text, lower, real_text, reals_text

    !> Decimal text of an integer, no blanks: "42".
    interface int_text
        module procedure int_text_default, int_text_i8
    end interface int_text

contains

    !> Comma-separated short form of a vector, for messages: "1.0000E-01, 2.0000E-01".
    pure function vector_text(v) result(text)
        real(wp), intent(in) :: v(:)
            !! the vector
        character(len=:), allocatable :: text
            !! its components, 5 significant digits each

        character(len=24) :: buf
        integer :: i

        text = ""
        do i = 1, size(v)
            write (buf, "(es11.4)") v(i)
            text = text//trim(adjustl(buf))
            if (i < size(v)) text = text//", "
        end do
    end function vector_text

    pure function int_text_default(value) result(text)
        integer, intent(in) :: value
            !! the integer
        character(len=:), allocatable :: text
            !! its digits

        character(len=24) :: buffer

        write (buffer, "(i0)") value
        text = trim(buffer)
    end function int_text_default

    pure function int_text_i8(value) result(text)
        integer(i8), intent(in) :: value
            !! the integer
        character(len=:), allocatable :: text
            !! its digits

        character(len=24) :: buffer

        write (buffer, "(i0)") value
        text = trim(buffer)
    end function int_text_i8

    !> ASCII lower case.
    pure function lower(text) result(low)
        character(len=*), intent(in) :: text
            !! any text
        character(len=len(text)) :: low
            !! A-Z turned into a-z

        integer :: i, code

        low = text
        do i = 1, len(text)
            code = iachar(text(i:i))
            if (code >= iachar("A") .and. code <= iachar("Z")) low(i:i) = achar(code + 32)
        end do
    end function lower

    !> The shortest text (up to 17 digits) that reads back as the same double.
    pure function real_text(value) result(text)
        real(wp), intent(in) :: value
            !! a finite number
        character(len=:), allocatable :: text
            !! its text, "0.5", "1", "512345.67", "1.0E+35"

        character(len=40) :: buffer, form
        character(len=80) :: message
        real(wp) :: back
        integer :: digits, stat

        do digits = 1, 17
            ! plain decimals for ordinary sizes, "1.5E+35" beyond
            if (value == 0.0_wp .or. (abs(value) >= 1.0e-3_wp .and. abs(value) < 1.0e15_wp)) &
                then
                write (form, "(a,i0,a)") "(g0.", digits, ")"
            else
                write (form, "(a,i0,a)") "(es30.", max(digits - 1, 1), ")"
            end if
            write (buffer, form) value
            read (buffer, *, iostat=stat, iomsg=message) back
            if (stat == 0 .and. back == value) exit
        end do
        text = trim(adjustl(buffer))
        ! g0.d writes 1.0 as "1."
        if (text(len(text):) == ".") text = text(1:len(text) - 1)
    end function real_text

    !> "(x, y, z)" with each component in its shortest exact form (real_text).
    pure function reals_text(values) result(text)
        real(wp), intent(in) :: values(:)
            !! the components
        character(len=:), allocatable :: text
            !! the vector as text

        integer :: i

        text = "("
        do i = 1, size(values)
            if (i > 1) text = text//", "
            text = text//real_text(values(i))
        end do
        text = text//")"
    end function reals_text

end module mpm_strings
