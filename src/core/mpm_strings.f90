!> Small text helpers for messages.
module mpm_strings
    use, intrinsic :: iso_c_binding, only: c_char, c_double, c_ptr, c_null_ptr, c_null_char
    use mpm_kinds, only: wp, i8
    implicit none
    private
    public :: vector_text, int_text, lower, real_text, reals_text, path_problem
    public :: max_path_bytes, max_name_bytes
    public :: fmt_real, fmt_below, fmt_vector, fmt_box, int_list, quoted_list, plain_list
    public :: join, text_or, yes_no, same, levenshtein, base_name, any_same
    public :: parse_real, number_invalid, number_finite, number_not_finite, number_too_large

    integer, parameter :: max_path_bytes = 4095
        !! longest path a system call takes [bytes] (Linux PATH_MAX 4096, with its NUL)
    integer, parameter :: max_name_bytes = 255
        !! longest file or folder name, one part of a path [bytes] (Linux NAME_MAX)

    !> Decimal text of an integer, no blanks: "42".
    interface int_text
        module procedure int_text_default, int_text_i8
    end interface int_text

    ! Decimal exponents beyond this are refused before conversion (no overflow while reading).
    integer, parameter :: max_decimal_exponent = 300
    ! What a token is as a number (parse_real; number_slow: valid, left to strtod)
    integer, parameter :: number_invalid = 0
        !! result of parse_real: not a number
    integer, parameter :: number_finite = 1
        !! result of parse_real: a finite number, converted
    integer, parameter :: number_slow = 2
    integer, parameter :: number_not_finite = 3
        !! result of parse_real: NaN or infinity
    integer, parameter :: number_too_large = 4
        !! result of parse_real: a decimal exponent beyond 300, out of range
    ! 10**k, k = 0..22: exact doubles (10**k = 5**k 2**k and 5**22 < 2**53)
    real(wp), parameter :: exact_powers(0:22) = [1.0e0_wp, 1.0e1_wp, 1.0e2_wp, 1.0e3_wp, &
        1.0e4_wp, 1.0e5_wp, 1.0e6_wp, 1.0e7_wp, 1.0e8_wp, 1.0e9_wp, 1.0e10_wp, 1.0e11_wp, &
        1.0e12_wp, 1.0e13_wp, 1.0e14_wp, 1.0e15_wp, 1.0e16_wp, 1.0e17_wp, 1.0e18_wp, 1.0e19_wp, &
        1.0e20_wp, 1.0e21_wp, 1.0e22_wp]

    ! allow(assumed-size): null-terminated C string passed to libc
    interface
        !> C's conversion of decimal text to double, correctly rounded (glibc); the "C" locale
        !> of a Fortran program reads "." as the decimal point.
        function c_strtod(text, end) bind(c, name="strtod") result(value)
            import :: c_char, c_double, c_ptr
            character(kind=c_char), intent(in) :: text(*)
                !! the number, null-terminated
            type(c_ptr), value :: end
                !! where to store the end of the number (NULL: nowhere)
            real(c_double) :: value
                !! the number
        end function c_strtod
    end interface

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

    ! ----------------------------------------------------------------------------------------
    ! Text of messages and summaries (from the case reader)
    ! ----------------------------------------------------------------------------------------

    !> Shortest text that reads back as x ("0.1", "1000000", "1e-5", "2.5e9"), or x rounded
    !> to `digits` significant digits. Plain decimals from 1e-4 to 1e7, exponents outside.
    pure function fmt_real(x, digits) result(text)
        real(wp), intent(in) :: x
            !! finite number
        integer, intent(in), optional :: digits
            !! significant digits (default: as many as needed to read back exactly)
        character(len=:), allocatable :: text

        character(len=40) :: buf
        character(len=:), allocatable :: mantissa
        character(len=20) :: form
        integer :: p, e, epos, nd, first, last
        real(wp) :: y

        if (x == 0.0_wp) then
            text = "0"
            return
        end if
        do p = 1, 17
            if (present(digits)) then
                if (p < digits) cycle
            end if
            write (form, "(a,i0,a)") "(es40.", p - 1, "e4)"
            write (buf, form) x
            read (buf, *) y
            if (present(digits) .or. y == x) exit
        end do
        buf = adjustl(buf)
        epos = index(buf, "E")
        read (buf(epos + 1:), *) e
        ! digits of the mantissa without sign, point and trailing zeros
        mantissa = ""
        first = merge(2, 1, buf(1:1) == "-")
        do p = first, epos - 1
            if (buf(p:p) /= ".") mantissa = mantissa//buf(p:p)
        end do
        last = len(mantissa)
        do while (last > 1 .and. mantissa(last:last) == "0")
            last = last - 1
        end do
        mantissa = mantissa(1:last)
        nd = len(mantissa)
        if (e >= 0 .and. e < 7) then
            if (nd <= e + 1) then
                text = mantissa//repeat("0", e + 1 - nd)
            else
                text = mantissa(1:e + 1)//"."//mantissa(e + 2:)
            end if
        else if (e < 0 .and. e >= -4) then
            text = "0."//repeat("0", -e - 1)//mantissa
        else if (nd > 1) then
            text = mantissa(1:1)//"."//mantissa(2:)//"e"//int_text(e)
        else
            text = mantissa//"e"//int_text(e)
        end if
        if (x < 0.0_wp) text = "-"//text
    end function fmt_real

    !> `x` with the fewest digits (6 or more) whose text still reads as below `limit`, so a
    !> message "A is above B" never shows B rounded up to A.
    pure function fmt_below(x, limit) result(text)
        real(wp), intent(in) :: x
            !! number to show (x < limit)
        real(wp), intent(in) :: limit
            !! number it must stay below
        character(len=:), allocatable :: text

        integer :: digits
        real(wp) :: y

        do digits = 6, 17
            text = fmt_real(x, digits)
            read (text, *) y
            if (y < limit) return
        end do
    end function fmt_below

    !> "(1, 2.5)"
    pure function fmt_vector(v, digits) result(text)
        real(wp), intent(in) :: v(:)
            !! components
        integer, intent(in), optional :: digits
            !! significant digits (default: exact)
        character(len=:), allocatable :: text

        integer :: i

        text = "("
        do i = 1, size(v)
            if (i > 1) text = text//", "
            text = text//fmt_real(v(i), digits)
        end do
        text = text//")"
    end function fmt_vector

    !> "[0, 1] x [0, 2]"
    pure function fmt_box(lower, upper, digits) result(text)
        real(wp), intent(in) :: lower(:)
            !! lower corner
        real(wp), intent(in) :: upper(:)
            !! upper corner
        integer, intent(in), optional :: digits
            !! significant digits (default: exact)
        character(len=:), allocatable :: text

        integer :: d

        text = ""
        do d = 1, size(lower)
            if (d > 1) text = text//" x "
            text = text//"["//fmt_real(lower(d), digits)//", "//fmt_real(upper(d), digits)//"]"
        end do
    end function fmt_box

    !> "40 x 20"
    pure function int_list(values, separator) result(text)
        integer, intent(in) :: values(:)
            !! integers
        character(len=*), intent(in) :: separator
            !! text between two integers
        character(len=:), allocatable :: text

        integer :: i

        text = ""
        do i = 1, size(values)
            if (i > 1) text = text//separator
            text = text//int_text(values(i))
        end do
    end function int_list

    !> '"a", "b", "c"'
    pure function quoted_list(names) result(text)
        character(len=*), intent(in) :: names(:)
            !! names (trailing blanks ignored)
        character(len=:), allocatable :: text

        integer :: i

        text = ""
        do i = 1, size(names)
            if (i > 1) text = text//", "
            text = text//'"'//trim(names(i))//'"'
        end do
    end function quoted_list

    !> "a, b, c"
    pure function plain_list(names) result(text)
        character(len=*), intent(in) :: names(:)
            !! names (trailing blanks ignored)
        character(len=:), allocatable :: text

        integer :: i

        text = ""
        do i = 1, size(names)
            if (i > 1) text = text//", "
            text = text//trim(names(i))
        end do
    end function plain_list

    !> "a.b", or "b" when the path is empty.
    pure function join(path, key) result(text)
        character(len=*), intent(in) :: path
            !! path of the parent ("" at the top level)
        character(len=*), intent(in) :: key
            !! key in the parent
        character(len=:), allocatable :: text

        if (len(path) == 0) then
            text = key
        else
            text = path//"."//key
        end if
    end function join

    !> The text of an allocatable string, or a default when it is unallocated (or empty).
    pure function text_or(str, default, empty_too) result(text)
        character(len=:), allocatable, intent(in) :: str
            !! string that may be unallocated
        character(len=*), intent(in) :: default
            !! text used instead
        logical, intent(in), optional :: empty_too
            !! also use the default for an empty string
        character(len=:), allocatable :: text

        text = default
        if (.not. allocated(str)) return
        if (len(str) == 0 .and. present(empty_too)) then
            if (empty_too) return
        end if
        text = str
    end function text_or

    !> "yes" or "no".
    pure function yes_no(flag) result(text)
        logical, intent(in) :: flag
            !! the flag
        character(len=:), allocatable :: text
            !! its text

        text = trim(merge("yes", "no ", flag))
    end function yes_no

    !> Equal strings, trailing blanks included (Fortran's == ignores them).
    pure logical function same(a, b)
        character(len=*), intent(in) :: a
            !! one string
        character(len=*), intent(in) :: b
            !! the other

        same = len(a) == len(b)
        if (same) same = a == b
    end function same

    !> Edit distance between two strings (insertions, deletions, substitutions).
    pure integer function levenshtein(a, b)
        character(len=*), intent(in) :: a
            !! one string
        character(len=*), intent(in) :: b
            !! the other

        integer :: previous(0:len(b)), current(0:len(b))
        integer :: i, j

        previous = [(j, j = 0, len(b))]
        do i = 1, len(a)
            current(0) = i
            do j = 1, len(b)
                current(j) = min(previous(j) + 1, current(j - 1) + 1, &
                    previous(j - 1) + merge(0, 1, a(i:i) == b(j:j)))
            end do
            previous = current
        end do
        levenshtein = previous(len(b))
    end function levenshtein

    !> File name without folder and extension: "inputs/column.json" -> "column".
    pure function base_name(path) result(name)
        character(len=*), intent(in) :: path
            !! file path
        character(len=:), allocatable :: name

        integer :: slash, dot

        slash = index(path, "/", back=.true.)
        name = path(slash + 1:)
        dot = index(name, ".", back=.true.)
        if (dot > 1) name = name(1:dot - 1)
    end function base_name

    !> Whether `key` is one of `names` (exactly, trailing blanks of the names ignored).
    pure logical function any_same(names, key)
        character(len=*), intent(in) :: names(:)
            !! names (trailing blanks ignored)
        character(len=*), intent(in) :: key
            !! key to find

        integer :: i

        any_same = .false.
        do i = 1, size(names)
            if (same(trim(names(i)), key)) any_same = .true.
        end do
    end function any_same
    !> A whitespace-free token as a real number ([sign] digits [. digits] [e|d [sign] digits]),
    !> NaN or infinity, correctly rounded: scan_number, and C's strtod where its fast path
    !> does not apply.
    subroutine parse_real(token, kind, value)
        character(len=*), intent(in) :: token
            !! one whitespace-free token
        integer, intent(out) :: kind
            !! number_invalid, number_finite (value set), number_not_finite or number_too_large
        real(wp), intent(out) :: value
            !! the number when kind is number_finite, else 0 [as written]

        call scan_number(token, kind, value)
        if (kind == number_slow) then
            ! syntax checked by scan_number; C knows no "d" exponent
            value = real(c_strtod(trim(fortran_exponent_to_c(token))//c_null_char, c_null_ptr), wp)
            kind = number_finite
        end if
    end subroutine parse_real

    !> Scan a token as a decimal number ([sign] digits [. digits] [e|d [sign] digits]), NaN or
    !> infinity. Most numbers are converted here: with at most 15 significant digits m and a
    !> power of ten 10**k, |k| <= 22, both m and 10**|k| are exact doubles, so one product or
    !> quotient is the correctly rounded value (Clinger's fast path); the others are left to
    !> C's strtod (number_slow).
    pure subroutine scan_number(token, kind, value)
        character(len=*), intent(in) :: token
            !! one whitespace-free token
        integer, intent(out) :: kind
            !! number_invalid, number_finite (value set), number_slow (valid, value not set),
            !! number_not_finite or number_too_large
        real(wp), intent(out) :: value
            !! the number when kind is number_finite, else 0 [as written]

        integer :: i, n, digit, digits, fraction_digits, significant, pending_zeros, exponent
        integer :: power
        integer :: exponent_sign, exponent_digits
        integer(i8) :: mantissa
        logical :: negative, seen_point, seen_nonzero, fast

        kind = number_invalid
        value = 0.0_wp
        n = len(token)
        if (n == 0) return
        i = 1
        negative = token(1:1) == "-"
        if (token(1:1) == "+" .or. token(1:1) == "-") i = 2
        if (i <= n) then
            select case (lower(token(i:n)))
            case ("nan", "inf", "infinity")
                kind = number_not_finite
                return
            case default
                continue
            end select
        end if
        ! mantissa: digits up to the last non-zero one; zeros after it are held in pending_zeros
        mantissa = 0
        digits = 0
        significant = 0
        pending_zeros = 0
        fraction_digits = 0
        seen_point = .false.
        seen_nonzero = .false.
        fast = .true.
        do while (i <= n)
            if (is_digit(token(i:i))) then
                digit = iachar(token(i:i)) - iachar("0")
                digits = digits + 1
                if (seen_point) fraction_digits = fraction_digits + 1
                if (digit == 0) then
                    if (seen_nonzero) pending_zeros = pending_zeros + 1
                else
                    seen_nonzero = .true.
                    if (significant + pending_zeros + 1 > 15) fast = .false.
                    if (fast) mantissa = mantissa*10_i8**(pending_zeros + 1) + digit
                    significant = significant + pending_zeros + 1
                    pending_zeros = 0
                end if
            else if (token(i:i) == "." .and. .not. seen_point) then
                seen_point = .true.
            else
                exit
            end if
            i = i + 1
        end do
        if (digits == 0) return
        exponent = 0
        if (i <= n) then
            if (index("eEdD", token(i:i)) == 0) return
            i = i + 1
            exponent_sign = 1
            if (i <= n) then
                if (token(i:i) == "+") then
                    i = i + 1
                else if (token(i:i) == "-") then
                    exponent_sign = -1
                    i = i + 1
                end if
            end if
            exponent_digits = 0
            do while (i <= n)
                if (.not. is_digit(token(i:i))) return
                exponent_digits = exponent_digits + 1
                ! saturate: only "far beyond the range" matters
                if (exponent < 100000) exponent = 10*exponent + (iachar(token(i:i)) - iachar("0"))
                i = i + 1
            end do
            if (exponent_digits == 0) return
            exponent = exponent_sign*exponent
        end if
        kind = number_finite
        if (.not. seen_nonzero) then
            value = 0.0_wp
            if (negative) value = -value
            return
        end if
        ! value = 0.d1d2... x 10**(significant + power), with mantissa = d1d2... (when fast)
        power = exponent - fraction_digits + pending_zeros
        if (significant + power > max_decimal_exponent) then
            kind = number_too_large
        else if (fast .and. abs(power) <= 22) then
            if (power >= 0) then
                value = real(mantissa, wp)*exact_powers(power)
            else
                value = real(mantissa, wp)/exact_powers(-power)
            end if
            if (negative) value = -value
        else
            kind = number_slow
        end if
    end subroutine scan_number

    !> A Fortran number with its exponent letter as C reads it: "1.5d3" -> "1.5e3".
    pure function fortran_exponent_to_c(token) result(text)
        character(len=*), intent(in) :: token
            !! a number checked by scan_number
        character(len=len(token)) :: text
            !! the same with "d" or "D" turned into "e"

        integer :: i

        text = token
        i = scan(text, "dD")
        if (i > 0) text(i:i) = "e"
    end function fortran_exponent_to_c

    !> A decimal digit.
    elemental logical function is_digit(c)
        character, intent(in) :: c
            !! one character

        is_digit = c >= "0" .and. c <= "9"
    end function is_digit

end module mpm_strings
