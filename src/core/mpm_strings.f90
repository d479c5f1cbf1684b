!> Small text helpers for messages.
module mpm_strings
    use mpm_kinds, only: wp, i8
    implicit none
    private
    public :: vector_text, int_text, lower, real_text, reals_text, path_problem
    public :: max_path_bytes, max_name_bytes

    integer, parameter :: max_path_bytes = 4095
        !! longest path a system call takes [bytes] (Linux PATH_MAX 4096, with its NUL)
    integer, parameter :: max_name_bytes = 255
        !! longest file or folder name, one part of a path [bytes] (Linux NAME_MAX)

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

    !> What makes `path` unusable as a file or folder name, "" when nothing: a path longer
    !> than max_path_bytes less `room` (what the program appends: ".tmp" to a file it writes,
    !> "/" and a file name to a folder), or a part between "/" longer than max_name_bytes
    !> less `part_room`. Bytes are counted, as the system does.
    pure function path_problem(path, room, part_room) result(problem)
        character(len=*), intent(in) :: path
            !! the path
        integer, intent(in) :: room
            !! bytes appended to the whole path
        integer, intent(in) :: part_room
            !! bytes appended to its last part
        character(len=:), allocatable :: problem

        integer :: first, last

        problem = ""
        if (len(path) > max_path_bytes - room) then
            problem = "the path is "//int_text(len(path))//" bytes long, at most "// &
                int_text(max_path_bytes - room)
            if (room > 0) problem = problem//" (a path has at most "// &
                int_text(max_path_bytes)//" bytes, and "//int_text(room)//" are added to it)"
            return
        end if
        first = 1
        do while (first <= len(path))
            last = index(path(first:), "/")
            if (last == 0) then
                last = len(path)
            else
                last = first + last - 2
            end if
            if (last - first + 1 > max_name_bytes - part_room) then
                problem = "its part '"//path(first:first + 19)//"...' is "// &
                    int_text(last - first + 1)//" bytes long, at most "// &
                    int_text(max_name_bytes - part_room)//" (a file or folder name has at "// &
                    "most "//int_text(max_name_bytes)//" bytes"
                if (part_room > 0) problem = problem//", and "//int_text(part_room)// &
                    " are added to it"
                problem = problem//")"
                return
            end if
            first = last + 2
        end do
    end function path_problem

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
