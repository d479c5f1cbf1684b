!> Small text helpers for messages.
module mpm_strings
    use mpm_kinds, only: wp
    implicit none
    private
    public :: vector_text, int_text

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

    !> Decimal text of an integer, no blanks: "42".
    pure function int_text(value) result(text)
        integer, intent(in) :: value
            !! the integer
        character(len=:), allocatable :: text
            !! its digits

        character(len=24) :: buffer

        write (buffer, "(i0)") value
        text = trim(buffer)
    end function int_text

end module mpm_strings
