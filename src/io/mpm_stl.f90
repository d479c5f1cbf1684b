!> Read STL triangle meshes: terrain surfaces exported from DEMs and closed surfaces of bodies.
!>
!> `read_stl` reads ASCII and binary STL. The format is decided by the file size, not by the
!> first word (binary files may start with "solid" too): a binary STL has 84 + 50 n bytes,
!> n being the unsigned 32-bit count at byte 80. When the size matches, the file is binary;
!> when it does not and the file starts with binary bytes, it is a binary STL of the wrong
!> size (truncated) and refused; otherwise it is parsed as ASCII (`solid` / `facet normal` /
!> `outer loop` / 3 x `vertex` / `endloop` / `endfacet` / `endsolid`, keywords in any case,
!> separated by any whitespace, several solids one after the other allowed).
!>
!> Binary numbers are little-endian (the count an unsigned 32-bit integer, coordinates IEEE
!> real32), read as stored: this reader assumes a little-endian machine (x86-64, AArch64).
!>
!> Coordinates become `x*scale + offset` in double precision. Normals are recomputed from the
!> corner order (right-hand rule); the normals in the file are never used. Degenerate
!> triangles (zero area to round-off) are skipped and counted. Every problem with the file is
!> an error with code exit_input whose message names the file and the case-file key.
!>
!> `check_closed` tells whether a mesh is the closed, consistently oriented surface of a body.
module mpm_stl
    use, intrinsic :: iso_c_binding, only: c_char, c_double, c_ptr, c_null_ptr
    use, intrinsic :: iso_fortran_env, only: int16, int32, real32
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_input, exit_other
    use mpm_filesystem, only: file_exists, directory_exists, c_string
    use mpm_strings, only: lower, real_text, vector_text => reals_text, i8_text => int_text
    implicit none
    private
    public :: stl_mesh_type, read_stl, check_closed, enclosed_volume
    public :: stl_coordinate_limit

    real(wp), parameter :: stl_coordinate_limit = 1.0e30_wp
        !! largest |coordinate| accepted after scale and offset, so that edge lengths, areas
        !! and normals never overflow [m]

    !> A triangle mesh read from an STL file.
    type :: stl_mesh_type
        integer :: n = 0
            !! triangles kept (the degenerate ones are skipped)
        real(wp), allocatable :: vertex(:, :, :)
            !! corners (coordinate, corner 1..3, triangle), after scale and offset [m]
        real(wp), allocatable :: normal(:, :)
            !! unit normal (coordinate, triangle), (v2 - v1) x (v3 - v1) normalised: the corners
            !! turn counter-clockwise seen from where the normal points [-]
        real(wp), allocatable :: area(:)
            !! area of each triangle [m2]
        integer, allocatable :: source(:)
            !! number of each triangle in the file (1-based; differs from its position in the
            !! mesh once a degenerate triangle was skipped), for messages
        real(wp) :: lo(3) = 0.0_wp
            !! lower corner of the bounding box of the triangles kept [m]
        real(wp) :: hi(3) = 0.0_wp
            !! upper corner of the bounding box of the triangles kept [m]
        integer :: skipped = 0
            !! degenerate triangles (zero area to round-off) found in the file and skipped
        logical :: binary = .false.
            !! the file was a binary STL (else ASCII)
    end type stl_mesh_type

    ! Binary layout: 80-byte header, uint32 count, then 50-byte records (normal and 3 corners as
    ! 12 real32, then a 2-byte attribute), read as 25 16-bit words per record.
    integer(i8), parameter :: header_bytes = 84_i8
    integer(i8), parameter :: record_bytes = 50_i8
    integer, parameter :: record_words = 25
    integer, parameter :: chunk_records = 32768
    ! ASCII: bytes loaded at a time, longest token kept, bytes looked at to tell text from binary
    integer, parameter :: text_chunk = 65536
    integer, parameter :: token_length = 128
    integer, parameter :: sniff_bytes = 512
    ! A triangle is degenerate when 2 area <= degenerate_tolerance * (longest edge)**2: the
    ! cross product of its edges is then at the level of its own round-off (a few epsilon times
    ! the product of the edge lengths), so the normal has no direction.
    real(wp), parameter :: degenerate_tolerance = 8.0_wp*epsilon(1.0_wp)
    ! Decimal exponents beyond this are refused before conversion (no overflow while reading).
    integer, parameter :: max_decimal_exponent = 300
    character(len=*), parameter :: axis_names = "xyz"
    ! What a token is as a number (scan_number)
    integer, parameter :: number_invalid = 0, number_finite = 1, number_slow = 2, &
        number_not_finite = 3, number_too_large = 4
    ! 10**k, k = 0..22: exact doubles (10**k = 5**k 2**k and 5**22 < 2**53)
    real(wp), parameter :: exact_powers(0:22) = [1.0e0_wp, 1.0e1_wp, 1.0e2_wp, 1.0e3_wp, &
        1.0e4_wp, 1.0e5_wp, 1.0e6_wp, 1.0e7_wp, 1.0e8_wp, 1.0e9_wp, 1.0e10_wp, 1.0e11_wp, &
        1.0e12_wp, 1.0e13_wp, 1.0e14_wp, 1.0e15_wp, 1.0e16_wp, 1.0e17_wp, 1.0e18_wp, 1.0e19_wp, &
        1.0e20_wp, 1.0e21_wp, 1.0e22_wp]
    ! check_closed numbers corners 1..3n and uses tables of up to 4 x 3n slots, default
    ! integers: n <= (2**31 - 1)/12
    integer, parameter :: max_closed_triangles = 178956970
    ! Low 32 bits (hash of check_closed)
    integer(i8), parameter :: mask32 = 4294967295_i8

    !> What a reading needs besides the data: the file, its key and the transformation.
    type :: stl_context_type
        character(len=:), allocatable :: path
            !! the STL file as given
        character(len=:), allocatable :: key
            !! case-file key naming it (not allocated: none)
        real(wp) :: scale = 1.0_wp
            !! factor on the file's coordinates [m per unit]
        real(wp) :: offset(3) = 0.0_wp
            !! translation after scaling [m]
    end type stl_context_type

    !> Buffered reading of a text file through stream access, with a line counter.
    type :: text_reader_type
        integer :: unit = -1
            !! stream unit of the open file
        integer(i8) :: size = 0
            !! file size [bytes]
        integer(i8) :: next = 1
            !! file position of the first byte not loaded yet
        character(len=text_chunk) :: buffer = ""
            !! bytes loaded
        integer :: filled = 0
            !! bytes of buffer in use
        integer :: at = 1
            !! position in buffer of the current character
        integer :: line = 1
            !! line of the current character
        integer :: last_line = 1
            !! line of the last token read
        logical :: eof = .false.
            !! no character left (end of the file, or a read error when stat /= 0)
        integer :: stat = 0
            !! iostat of a failed read, else 0
        character(len=256) :: message = ""
            !! iomsg of a failed read
    end type text_reader_type

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

    !> Read an STL file (ASCII or binary) into `mesh`, corners transformed to x*scale + offset.
    subroutine read_stl(path, mesh, error, scale, offset, key)
        character(len=*), intent(in) :: path
            !! STL file, absolute or relative to the working folder
        type(stl_mesh_type), intent(out) :: mesh
            !! the triangles read (n = 0 on error)
        type(error_type), allocatable, intent(out) :: error
            !! set when the file cannot be used (exit_input; exit_other when out of memory);
            !! the message names the file and `key`
        real(wp), intent(in), optional :: scale
            !! factor applied to every coordinate before `offset`, > 0 (default 1) [m per unit]
        real(wp), intent(in), optional :: offset(3)
            !! translation added after scaling (default 0) [m]
        character(len=*), intent(in), optional :: key
            !! case-file key that names the file, for messages (e.g. "contact.file")

        type(stl_context_type) :: ctx
        integer(i8) :: size, count
        integer :: unit, stat
        character(len=256) :: message
        character(len=sniff_bytes) :: head
        integer(int32) :: count_word
        integer :: nhead

        ctx%path = path
        if (present(key)) ctx%key = key
        if (present(scale)) then
            if (.not. ieee_is_finite(scale)) then
                call refuse(error, ctx, "the scale must be a finite number > 0")
                return
            end if
            if (scale <= 0.0_wp) then
                call refuse(error, ctx, "the scale must be > 0, not "//real_text(scale))
                return
            end if
            ctx%scale = scale
        end if
        if (present(offset)) then
            if (.not. all(ieee_is_finite(offset))) then
                call refuse(error, ctx, "the offset must be 3 finite numbers")
                return
            end if
            if (any(abs(offset) > stl_coordinate_limit)) then
                call refuse(error, ctx, "the offset "//vector_text(offset)//" is beyond "// &
                    real_text(stl_coordinate_limit)//" m")
                return
            end if
            ctx%offset = offset
        end if

        if (directory_exists(path)) then
            call refuse(error, ctx, "it is a folder, not a file")
            return
        end if
        if (.not. file_exists(path)) then
            call refuse(error, ctx, "the file does not exist")
            return
        end if
        open (newunit=unit, file=path, access="stream", form="unformatted", action="read", &
            status="old", iostat=stat, iomsg=message)
        if (stat /= 0) then
            call refuse(error, ctx, "the file cannot be opened (permission denied?): "// &
                trim(message))
            return
        end if
        inquire (unit=unit, size=size)
        if (size < 0) then
            call refuse(error, ctx, "the size of the file cannot be found (not a regular file?)")
        else if (size == 0) then
            call refuse(error, ctx, "the file is empty")
        else
            nhead = int(min(size, int(sniff_bytes, i8)))
            head = ""
            read (unit, pos=1, iostat=stat, iomsg=message) head(1:nhead)
            if (stat /= 0) then
                call refuse(error, ctx, "the file cannot be read: "//trim(message))
            else if (size >= header_bytes) then
                read (unit, pos=81, iostat=stat, iomsg=message) count_word
                if (stat /= 0) then
                    call refuse(error, ctx, "the file cannot be read: "//trim(message))
                else
                    count = unsigned_count(count_word)
                    if (size == header_bytes + record_bytes*count) then
                        call read_binary(unit, count, ctx, mesh, error)
                    else if (is_text(head(1:nhead))) then
                        call read_ascii(unit, size, head(1:nhead), ctx, mesh, error)
                    else
                        call refuse(error, ctx, "binary STL of the wrong size: its header "// &
                            "announces "//i8_text(count)//" triangles, which take 84 + 50 x "// &
                            i8_text(count)//" = "//i8_text(header_bytes + record_bytes*count)// &
                            " bytes, but the file has "//i8_text(size)//" bytes"// &
                            size_hint(size < header_bytes + record_bytes*count))
                    end if
                end if
            else if (is_text(head(1:nhead))) then
                call read_ascii(unit, size, head(1:nhead), ctx, mesh, error)
            else
                call refuse(error, ctx, "it holds binary bytes but has only "//i8_text(size)// &
                    " bytes, less than the 84 bytes of a binary STL header (truncated?)")
            end if
        end if
        ! a file only read: a failing close loses nothing, but say so if all else went well
        close (unit, iostat=stat, iomsg=message)
        if (stat /= 0 .and. .not. allocated(error)) then
            call refuse(error, ctx, "the file cannot be closed: "//trim(message))
        end if
        if (allocated(error)) then
            mesh%n = 0
            return
        end if
        call finish_mesh(mesh, ctx, error)
        if (allocated(error)) mesh%n = 0
    end subroutine read_stl

    ! ------------------------------------------------------------------------------------------
    ! Binary
    ! ------------------------------------------------------------------------------------------

    !> The triangles of a binary STL whose size was checked against its count.
    subroutine read_binary(unit, count, ctx, mesh, error)
        integer, intent(in) :: unit
            !! open stream unit
        integer(i8), intent(in) :: count
            !! triangles announced by the header, consistent with the file size
        type(stl_context_type), intent(in) :: ctx
            !! file, key and transformation
        type(stl_mesh_type), intent(inout) :: mesh
            !! receives the triangles
        type(error_type), allocatable, intent(out) :: error
            !! set on a read error or a non-finite coordinate

        integer(int16), allocatable :: words(:, :)
        integer(int32) :: bits
        real(wp) :: raw(3, 3)
        integer :: n, first, m, r, t, corner, axis, f, stat
        character(len=256) :: message

        mesh%binary = .true.
        if (count > huge(n)) then
            call refuse(error, ctx, "binary STL of "//i8_text(count)//" triangles: more than "// &
                i8_text(int(huge(n), i8))//" are not supported")
            return
        end if
        n = int(count)
        if (n == 0) return
        call reserve(mesh, n, ctx, error)
        if (allocated(error)) return
        allocate (words(record_words, min(chunk_records, n)), stat=stat, errmsg=message)
        if (stat /= 0) then
            call fatal_error(error, describe_file(ctx)//": out of memory for a read buffer: "// &
                trim(message), exit_other)
            return
        end if
        first = 1
        do while (first <= n)
            m = min(chunk_records, n - first + 1)
            read (unit, pos=header_bytes + record_bytes*(first - 1) + 1, iostat=stat, &
                iomsg=message) words(:, 1:m)
            if (stat /= 0) then
                call refuse(error, ctx, "the file cannot be read (triangles "// &
                    i8_text(int(first, i8))//" and after): "//trim(message))
                return
            end if
            do r = 1, m
                t = first + r - 1
                do corner = 1, 3
                    do axis = 1, 3
                        ! 12 real32 per record: the normal (ignored), then the corners
                        f = 3*corner + axis
                        bits = ior(iand(int(words(2*f - 1, r), int32), int(z'FFFF', int32)), &
                            ishft(int(words(2*f, r), int32), 16))
                        ! exponent bits all set: NaN or infinity (tested on the bits, so that
                        ! a signalling NaN never reaches a floating-point operation)
                        if (iand(ishft(bits, -23), 255_int32) == 255_int32) then
                            call refuse(error, ctx, "triangle "//i8_text(int(t, i8))// &
                                " has a NaN or infinite coordinate (corner "// &
                                i8_text(int(corner, i8))//", "//axis_names(axis:axis)//")")
                            return
                        end if
                        raw(axis, corner) = real(transfer(bits, 1.0_real32), wp)
                    end do
                end do
                call store_triangle(mesh, raw, t, 0, ctx, error)
                if (allocated(error)) return
            end do
            first = first + m
        end do
    end subroutine read_binary

    !> The uint32 stored in `word` (read as a signed 32-bit integer), as a 64-bit integer.
    pure function unsigned_count(word) result(count)
        integer(int32), intent(in) :: word
            !! the 4 bytes of the count, little-endian, as read
        integer(i8) :: count
            !! the count, 0 to 2**32 - 1

        count = int(word, i8)
        if (count < 0) count = count + 4294967296_i8
    end function unsigned_count

    ! ------------------------------------------------------------------------------------------
    ! ASCII
    ! ------------------------------------------------------------------------------------------

    !> The triangles of an ASCII STL.
    subroutine read_ascii(unit, size, head, ctx, mesh, error)
        integer, intent(in) :: unit
            !! open stream unit
        integer(i8), intent(in) :: size
            !! file size [bytes]
        character(len=*), intent(in) :: head
            !! first bytes of the file (to skip a UTF-8 byte order mark)
        type(stl_context_type), intent(in) :: ctx
            !! file, key and transformation
        type(stl_mesh_type), intent(inout) :: mesh
            !! receives the triangles
        type(error_type), allocatable, intent(out) :: error
            !! set when the text is not a complete ASCII STL

        type(text_reader_type) :: reader
        character(len=token_length) :: token
        integer :: length, line, facet, corner, axis, first_line
        real(wp) :: raw(3, 3), value
        logical :: finite

        mesh%binary = .false.
        reader%unit = unit
        reader%size = size
        reader%next = 1
        if (len(head) >= 3) then
            if (head(1:3) == char(239)//char(187)//char(191)) reader%next = 4
        end if

        call next_token(reader, token, length, line)
        call check_read(reader, ctx, error)
        if (allocated(error)) return
        if (length == 0) then
            call refuse(error, ctx, "it holds only blanks (expected an STL: 'solid' first)")
            return
        end if
        if (lower(token(1:min(length, token_length))) /= "solid") then
            call refuse(error, ctx, "line "//i8_text(int(line, i8))//": expected 'solid' "// &
                "(the first word of an ASCII STL), found '"//shown(token, length)// &
                "': it is neither an ASCII STL nor a binary STL (whose size would be 84 + 50 n)")
            return
        end if
        call skip_line(reader)
        facet = 0
        solids: do
            call next_token(reader, token, length, line)
            call check_read(reader, ctx, error)
            if (allocated(error)) return
            if (length == 0) then
                call refuse(error, ctx, "line "//i8_text(int(line, i8))//": the file ends "// &
                    "before 'endsolid' (truncated?)")
                return
            end if
            select case (lower(token(1:min(length, token_length))))
            case ("facet")
                if (facet == huge(facet)) then
                    call refuse(error, ctx, "more than "//i8_text(int(huge(facet), i8))// &
                        " facets are not supported")
                    return
                end if
                facet = facet + 1
                first_line = line
                call expect("normal")
                if (allocated(error)) return
                do axis = 1, 3
                    ! the normal of the file is read for the syntax only: it is recomputed
                    call number(value, finite, 0, axis)
                    if (allocated(error)) return
                end do
                call expect("outer")
                if (allocated(error)) return
                call expect("loop")
                if (allocated(error)) return
                do corner = 1, 3
                    call expect("vertex")
                    if (allocated(error)) return
                    do axis = 1, 3
                        call number(raw(axis, corner), finite, corner, axis)
                        if (allocated(error)) return
                        if (.not. finite) then
                            call refuse(error, ctx, "line "//i8_text(int(line, i8))// &
                                ": triangle "//i8_text(int(facet, i8))//" has a NaN or "// &
                                "infinite coordinate (corner "//i8_text(int(corner, i8))//", "// &
                                axis_names(axis:axis)//": '"//shown(token, length)//"')")
                            return
                        end if
                    end do
                end do
                call expect("endloop")
                if (allocated(error)) return
                call expect("endfacet")
                if (allocated(error)) return
                call reserve(mesh, mesh%n + 1, ctx, error)
                if (allocated(error)) return
                call store_triangle(mesh, raw, facet, first_line, ctx, error)
                if (allocated(error)) return
            case ("endsolid")
                call skip_line(reader)
                call next_token(reader, token, length, line)
                call check_read(reader, ctx, error)
                if (allocated(error)) return
                if (length == 0) exit solids
                if (lower(token(1:min(length, token_length))) /= "solid") then
                    call refuse(error, ctx, "line "//i8_text(int(line, i8))//": expected "// &
                        "'solid' or the end of the file after 'endsolid', found '"// &
                        shown(token, length)//"'")
                    return
                end if
                call skip_line(reader)
            case default
                call refuse(error, ctx, "line "//i8_text(int(line, i8))//": expected 'facet' "// &
                    "or 'endsolid', found '"//shown(token, length)//"'")
                return
            end select
        end do solids

    contains

        !> The next token must be the keyword `word` (any case).
        subroutine expect(word)
            character(len=*), intent(in) :: word
                !! the keyword, lower case

            call next_token(reader, token, length, line)
            call check_read(reader, ctx, error)
            if (allocated(error)) return
            if (length == 0) then
                call refuse(error, ctx, "line "//i8_text(int(line, i8))//": the file ends "// &
                    "where '"//word//"' was expected (truncated?)")
            else if (lower(token(1:min(length, token_length))) /= word) then
                call refuse(error, ctx, "line "//i8_text(int(line, i8))//": expected '"// &
                    word//"', found '"//shown(token, length)//"'")
            end if
        end subroutine expect

        !> The next token must be a number; NaN and infinity are numbers that are not finite.
        subroutine number(value, finite, corner, axis)
            real(wp), intent(out) :: value
                !! the number (0 when not finite) [file units]
            logical, intent(out) :: finite
                !! false for NaN and infinity
            integer, intent(in) :: corner
                !! vertex 1..3 of the current facet, 0 for its normal
            integer, intent(in) :: axis
                !! component 1..3 (x, y, z)

            integer :: kind

            value = 0.0_wp
            finite = .false.
            call next_token(reader, token, length, line)
            call check_read(reader, ctx, error)
            if (allocated(error)) return
            if (length == 0) then
                call refuse(error, ctx, "line "//i8_text(int(line, i8))//": the file ends "// &
                    "where a number ("//number_description(facet, corner, axis)// &
                    ") was expected (truncated?)")
                return
            end if
            kind = number_invalid
            if (length <= token_length) call scan_number(token(1:length), kind, value)
            if (kind == number_too_large) then
                call refuse(error, ctx, "line "//i8_text(int(line, i8))//": the number '"// &
                    shown(token, length)//"' ("//number_description(facet, corner, axis)// &
                    ") is out of range")
                return
            else if (kind == number_not_finite) then
                value = 0.0_wp
                return
            else if (kind == number_finite) then
                finite = .true.
                return
            else if (kind == number_slow) then
                ! syntax checked by scan_number; C knows no "d" exponent
                value = real(c_strtod(c_string(fortran_exponent_to_c(token(1:length))), &
                    c_null_ptr), wp)
                finite = .true.
                return
            end if
            call refuse(error, ctx, "line "//i8_text(int(line, i8))//": expected a number ("// &
                number_description(facet, corner, axis)//"), found '"//shown(token, length)// &
                "'")

        end subroutine number

    end subroutine read_ascii

    !> What a number of an ASCII facet is, for messages: "coordinate x of vertex 2 of facet 5".
    pure function number_description(facet, corner, axis) result(text)
        integer, intent(in) :: facet
            !! facet number in the file
        integer, intent(in) :: corner
            !! vertex 1..3, 0 for the normal
        integer, intent(in) :: axis
            !! component 1..3 (x, y, z)
        character(len=:), allocatable :: text
            !! the description

        if (corner == 0) then
            text = "component "//axis_names(axis:axis)//" of the normal of facet "// &
                i8_text(int(facet, i8))
        else
            text = "coordinate "//axis_names(axis:axis)//" of vertex "// &
                i8_text(int(corner, i8))//" of facet "//i8_text(int(facet, i8))
        end if
    end function number_description

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

    !> The next whitespace-separated token (length 0 at the end of the file).
    subroutine next_token(reader, token, length, line)
        type(text_reader_type), intent(inout) :: reader
            !! the reader, left on the character after the token
        character(len=token_length), intent(out) :: token
            !! the token (its first token_length characters)
        integer, intent(out) :: length
            !! its length (may exceed token_length); 0 at the end of the file
        integer, intent(out) :: line
            !! line the token is on (at the end of the file: the line of the last token)

        character :: c

        token = ""
        length = 0
        do
            call load(reader)
            if (reader%eof) then
                line = reader%last_line
                return
            end if
            c = reader%buffer(reader%at:reader%at)
            if (.not. is_space(c)) exit
            if (c == achar(10)) reader%line = reader%line + 1
            reader%at = reader%at + 1
        end do
        line = reader%line
        reader%last_line = reader%line
        do
            call load(reader)
            if (reader%eof) return
            c = reader%buffer(reader%at:reader%at)
            if (is_space(c)) return
            if (length < huge(length)) length = length + 1
            if (length <= token_length) token(length:length) = c
            reader%at = reader%at + 1
        end do
    end subroutine next_token

    !> Skip the rest of the current line (a solid's name), line feed included.
    subroutine skip_line(reader)
        type(text_reader_type), intent(inout) :: reader
            !! the reader, left at the start of the next line

        character :: c

        do
            call load(reader)
            if (reader%eof) return
            c = reader%buffer(reader%at:reader%at)
            reader%at = reader%at + 1
            if (c == achar(10)) then
                reader%line = reader%line + 1
                return
            end if
        end do
    end subroutine skip_line

    !> Make sure the buffer holds the current character, loading the next chunk when needed.
    subroutine load(reader)
        type(text_reader_type), intent(inout) :: reader
            !! the reader; eof is set at the end of the file or on a read error (stat /= 0)

        integer :: m, stat
        character(len=256) :: message

        if (reader%at <= reader%filled .or. reader%eof) return
        if (reader%next > reader%size) then
            reader%eof = .true.
            return
        end if
        m = int(min(int(text_chunk, i8), reader%size - reader%next + 1))
        read (reader%unit, pos=reader%next, iostat=stat, iomsg=message) reader%buffer(1:m)
        if (stat /= 0) then
            reader%stat = stat
            reader%message = message
            reader%eof = .true.
            return
        end if
        reader%next = reader%next + m
        reader%filled = m
        reader%at = 1
    end subroutine load

    !> An error when the reader stopped on a read error.
    subroutine check_read(reader, ctx, error)
        type(text_reader_type), intent(in) :: reader
            !! the reader after a token
        type(stl_context_type), intent(in) :: ctx
            !! file and key for the message
        type(error_type), allocatable, intent(out) :: error
            !! set when reading failed

        if (reader%stat /= 0) call refuse(error, ctx, "the file cannot be read (line "// &
            i8_text(int(reader%line, i8))//"): "//trim(reader%message))
    end subroutine check_read

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

    ! ------------------------------------------------------------------------------------------
    ! Mesh building
    ! ------------------------------------------------------------------------------------------

    !> Room for at least `needed` triangles (capacity doubles, so appending is O(1) on average).
    subroutine reserve(mesh, needed, ctx, error)
        type(stl_mesh_type), intent(inout) :: mesh
            !! mesh being filled; its first mesh%n triangles are kept
        integer, intent(in) :: needed
            !! triangles the arrays must hold
        type(stl_context_type), intent(in) :: ctx
            !! file and key for the message
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_other) when out of memory

        integer :: capacity
        real(wp), allocatable :: vertex(:, :, :), normal(:, :), area(:)
        integer, allocatable :: source(:)
        integer :: stat
        character(len=256) :: message

        capacity = 0
        if (allocated(mesh%area)) capacity = size(mesh%area)
        if (needed <= capacity) return
        if (capacity > 0) then
            capacity = max(needed, int(min(2_i8*capacity, int(huge(capacity), i8))))
        else
            capacity = needed
        end if
        allocate (vertex(3, 3, capacity), normal(3, capacity), area(capacity), &
            source(capacity), stat=stat, errmsg=message)
        if (stat /= 0) then
            call fatal_error(error, describe_file(ctx)//": out of memory for "// &
                i8_text(int(capacity, i8))//" triangles: "//trim(message), exit_other)
            return
        end if
        if (mesh%n > 0) then
            vertex(:, :, 1:mesh%n) = mesh%vertex(:, :, 1:mesh%n)
            normal(:, 1:mesh%n) = mesh%normal(:, 1:mesh%n)
            area(1:mesh%n) = mesh%area(1:mesh%n)
            source(1:mesh%n) = mesh%source(1:mesh%n)
        end if
        call move_alloc(vertex, mesh%vertex)
        call move_alloc(normal, mesh%normal)
        call move_alloc(area, mesh%area)
        call move_alloc(source, mesh%source)
    end subroutine reserve

    !> Transform one triangle of finite file coordinates and append it unless degenerate.
    subroutine store_triangle(mesh, raw, number, line, ctx, error)
        type(stl_mesh_type), intent(inout) :: mesh
            !! mesh with room for one more triangle
        real(wp), intent(in) :: raw(3, 3)
            !! corners as in the file (coordinate, corner), finite [file units]
        integer, intent(in) :: number
            !! number of the triangle in the file
        integer, intent(in) :: line
            !! line of its 'facet' in an ASCII file (0: binary)
        type(stl_context_type), intent(in) :: ctx
            !! file, key and transformation
        type(error_type), allocatable, intent(out) :: error
            !! set when a coordinate is beyond stl_coordinate_limit after the transformation

        real(wp) :: x(3, 3), e1(3), e2(3), e3(3), c(3), twice_area, longest2
        integer :: corner, axis
        logical :: too_far

        do corner = 1, 3
            do axis = 1, 3
                ! scale > 1 is checked first so that the product cannot overflow
                too_far = .false.
                if (ctx%scale > 1.0_wp) too_far = abs(raw(axis, corner)) > &
                    stl_coordinate_limit/ctx%scale
                if (.not. too_far) then
                    x(axis, corner) = raw(axis, corner)*ctx%scale + ctx%offset(axis)
                    too_far = abs(x(axis, corner)) > stl_coordinate_limit
                end if
                if (too_far) then
                    call refuse(error, ctx, line_prefix(line)//"triangle "// &
                        i8_text(int(number, i8))// &
                        " has the coordinate "//real_text(raw(axis, corner))//" (corner "// &
                        i8_text(int(corner, i8))//", "//axis_names(axis:axis)//"), beyond "// &
                        real_text(stl_coordinate_limit)//" m after scale and offset "// &
                        "(wrong units?)")
                    return
                end if
            end do
        end do
        e1 = x(:, 2) - x(:, 1)
        e2 = x(:, 3) - x(:, 1)
        e3 = x(:, 3) - x(:, 2)
        c = [e1(2)*e2(3) - e1(3)*e2(2), e1(3)*e2(1) - e1(1)*e2(3), e1(1)*e2(2) - e1(2)*e2(1)]
        twice_area = norm2(c)
        longest2 = max(dot_product(e1, e1), dot_product(e2, e2), dot_product(e3, e3))
        if (twice_area <= degenerate_tolerance*longest2) then
            mesh%skipped = mesh%skipped + 1
            return
        end if
        mesh%n = mesh%n + 1
        mesh%vertex(:, :, mesh%n) = x
        mesh%normal(:, mesh%n) = c/twice_area
        mesh%area(mesh%n) = 0.5_wp*twice_area
        mesh%source(mesh%n) = number
    end subroutine store_triangle

    !> Trim the arrays to n triangles, set the bounding box; refuse a mesh without triangles.
    subroutine finish_mesh(mesh, ctx, error)
        type(stl_mesh_type), intent(inout) :: mesh
            !! mesh read
        type(stl_context_type), intent(in) :: ctx
            !! file and key for the message
        type(error_type), allocatable, intent(out) :: error
            !! set when no triangle is left

        real(wp), allocatable :: vertex(:, :, :), normal(:, :), area(:)
        integer, allocatable :: source(:)
        integer :: axis

        if (mesh%n == 0) then
            if (mesh%skipped > 0) then
                call refuse(error, ctx, "zero triangles: all "//i8_text(int(mesh%skipped, i8))// &
                    " triangles are degenerate (zero area)")
            else
                call refuse(error, ctx, "zero triangles: the file holds no triangle")
            end if
            return
        end if
        if (size(mesh%area) > mesh%n) then
            vertex = mesh%vertex(:, :, 1:mesh%n)
            normal = mesh%normal(:, 1:mesh%n)
            area = mesh%area(1:mesh%n)
            source = mesh%source(1:mesh%n)
            call move_alloc(vertex, mesh%vertex)
            call move_alloc(normal, mesh%normal)
            call move_alloc(area, mesh%area)
            call move_alloc(source, mesh%source)
        end if
        do axis = 1, 3
            mesh%lo(axis) = minval(mesh%vertex(axis, :, :))
            mesh%hi(axis) = maxval(mesh%vertex(axis, :, :))
        end do
    end subroutine finish_mesh

    ! ------------------------------------------------------------------------------------------
    ! Closed surfaces
    ! ------------------------------------------------------------------------------------------

    !> Whether a mesh is a closed, consistently oriented surface: corners merged by exact
    !> equality of their coordinates, every edge belongs to exactly two triangles that traverse
    !> it in opposite directions. Self-intersections, several shells and the side the normals
    !> point to (see enclosed_volume) are not checked. Hash tables: O(n) expected time, at most
    !> about 170 bytes per triangle on top of the mesh.
    subroutine check_closed(mesh, closed, message, error)
        type(stl_mesh_type), intent(in) :: mesh
            !! mesh read by read_stl
        logical, intent(out) :: closed
            !! true when the surface is closed and consistently oriented
        character(len=:), allocatable, intent(out) :: message
            !! why not (the first offending edge in triangle order, its triangles by their number
            !! in the file, how many edges have that problem), or a short confirmation
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_other) when out of memory or the mesh is too large to index

        integer, allocatable :: id(:), table(:), uses(:)
        logical, allocatable :: same_direction(:)
        integer :: ncorner, nvertex, nedge, nslot, c, e, s, stat
        integer :: nopen, nshared, nflipped, first_open, first_shared, first_flipped
        character(len=256) :: alloc_message

        closed = .false.
        if (mesh%n == 0) then
            message = "the mesh has no triangles"
            return
        end if
        ! corners and directed edges are numbered 3 (t - 1) + k
        if (mesh%n > max_closed_triangles) then
            call fatal_error(error, "cannot check a surface of "//i8_text(int(mesh%n, i8))// &
                " triangles: at most "//i8_text(int(max_closed_triangles, i8))// &
                " are supported", exit_other)
            return
        end if
        ncorner = 3*mesh%n
        ! power of two, load factor at most 1/2
        nslot = 1
        do while (nslot < 2*ncorner)
            nslot = 2*nslot
        end do
        allocate (id(ncorner), table(nslot), stat=stat, errmsg=alloc_message)
        if (stat /= 0) then
            call out_of_memory()
            return
        end if

        ! Merge corners: equal coordinates, one vertex number.
        table = 0
        nvertex = 0
        do c = 1, ncorner
            s = int(iand(corner_hash(c), int(nslot - 1, i8))) + 1
            do
                if (table(s) == 0) then
                    table(s) = c
                    nvertex = nvertex + 1
                    id(c) = nvertex
                    exit
                else if (all(xyz(table(s)) == xyz(c))) then
                    id(c) = id(table(s))
                    exit
                end if
                s = iand(s, nslot - 1) + 1
            end do
        end do

        ! Undirected edges: table(s) is the first directed edge that uses one, uses(s) how many
        ! do, same_direction(s) whether two of them traverse it the same way.
        deallocate (table)
        allocate (table(nslot), uses(nslot), same_direction(nslot), stat=stat, &
            errmsg=alloc_message)
        if (stat /= 0) then
            call out_of_memory()
            return
        end if
        table = 0
        uses = 0
        same_direction = .false.
        nedge = 0
        do e = 1, ncorner
            s = edge_slot(e)
            if (table(s) == 0) then
                table(s) = e
                nedge = nedge + 1
            else if (id(e) == id(table(s))) then
                same_direction(s) = .true.
            end if
            uses(s) = uses(s) + 1
        end do

        ! Classify each undirected edge once, at its first use, in triangle order.
        nopen = 0
        nshared = 0
        nflipped = 0
        first_open = 0
        first_shared = 0
        first_flipped = 0
        do e = 1, ncorner
            s = edge_slot(e)
            if (table(s) /= e) cycle
            if (uses(s) == 1) then
                nopen = nopen + 1
                if (first_open == 0) first_open = e
            else if (uses(s) > 2) then
                nshared = nshared + 1
                if (first_shared == 0) first_shared = e
            else if (same_direction(s)) then
                nflipped = nflipped + 1
                if (first_flipped == 0) first_flipped = e
            end if
        end do

        closed = nopen + nshared + nflipped == 0
        if (closed) then
            message = "closed and consistently oriented: "//i8_text(int(mesh%n, i8))// &
                " triangles, "//i8_text(int(nedge, i8))//" edges each shared by two "// &
                "triangles in opposite directions"
        else if (nopen > 0) then
            message = edge_text(first_open)//" belongs to 1 triangle (triangle "// &
                triangles_of(first_open)//" of the file): the surface is open"// &
                how_many(nopen, "edge belongs", "edges belong")//" to one triangle only)"
        else if (nshared > 0) then
            s = edge_slot(first_shared)
            message = edge_text(first_shared)//" is shared by "//i8_text(int(uses(s), i8))// &
                " triangles (triangles "//triangles_of(first_shared)//" of the file): the "// &
                "surface is not a manifold"//how_many(nshared, "edge is", "edges are")// &
                " shared by more than two triangles)"
        else
            message = edge_text(first_flipped)//" is traversed in the same direction by "// &
                "triangles "//triangles_of(first_flipped)//" of the file: the surface is "// &
                "inconsistently oriented, one of them is flipped"// &
                how_many(nflipped, "edge has", "edges have")//" this problem)"
        end if

    contains

        !> Coordinates of corner c [m].
        pure function xyz(c) result(x)
            integer, intent(in) :: c
                !! corner number, 3 (t - 1) + k
            real(wp) :: x(3)
                !! its coordinates [m]

            x = mesh%vertex(:, c - 3*((c - 1)/3), (c - 1)/3 + 1)
        end function xyz

        !> The corner after corner c in its triangle (3 -> 1): the end of directed edge c.
        pure integer function next_corner(c)
            integer, intent(in) :: c
                !! corner number, 3 (t - 1) + k

            next_corner = c + 1
            if (mod(c, 3) == 0) next_corner = c - 2
        end function next_corner

        !> Hash of the coordinates of corner c (equal coordinates, equal hash: -0 counts as 0).
        pure integer(i8) function corner_hash(c) result(h)
            integer, intent(in) :: c
                !! corner number, 3 (t - 1) + k

            real(wp) :: x(3)
            integer(i8) :: bits
            integer :: axis

            x = xyz(c)
            h = 0
            do axis = 1, 3
                bits = 0
                if (x(axis) /= 0.0_wp) bits = transfer(x(axis), bits)
                h = mix(h, iand(bits, mask32))
                h = mix(h, iand(ishft(bits, -32), mask32))
            end do
        end function corner_hash

        !> Slot of the undirected edge of directed edge e, inserted or found by its vertices.
        integer function edge_slot(e) result(s)
            integer, intent(in) :: e
                !! directed edge number: from corner e to corner next_corner(e)

            integer :: a, b

            a = min(id(e), id(next_corner(e)))
            b = max(id(e), id(next_corner(e)))
            s = int(iand(mix(mix(0_i8, int(a, i8)), int(b, i8)), int(nslot - 1, i8))) + 1
            do
                if (table(s) == 0) return
                if (min(id(table(s)), id(next_corner(table(s)))) == a .and. &
                    max(id(table(s)), id(next_corner(table(s)))) == b) return
                s = iand(s, nslot - 1) + 1
            end do
        end function edge_slot

        !> "edge from (x, y, z) to (x, y, z)" in the direction the triangle of edge e goes.
        function edge_text(e) result(text)
            integer, intent(in) :: e
                !! directed edge number
            character(len=:), allocatable :: text
                !! the edge for a message

            text = "edge from "//vector_text(xyz(e))//" to "//vector_text(xyz(next_corner(e)))
        end function edge_text

        !> File numbers of the triangles that use the undirected edge of e: "3", "3 and 7".
        function triangles_of(e) result(text)
            integer, intent(in) :: e
                !! the first directed edge that uses the undirected edge
            character(len=:), allocatable :: text
                !! the numbers in the file of the triangles that use it

            integer :: other, s, count, found

            s = edge_slot(e)
            count = uses(s)
            text = ""
            found = 0
            do other = e, ncorner
                if (edge_slot(other) /= s) cycle
                found = found + 1
                if (found > 1 .and. found == count) then
                    text = text//" and "
                else if (found > 1) then
                    text = text//", "
                end if
                text = text//i8_text(int(mesh%source((other - 1)/3 + 1), i8))
                if (found == count) exit
            end do
        end function triangles_of

        !> " (1 edge belongs" or " (3 edges belong".
        function how_many(count, one, several) result(text)
            integer, intent(in) :: count
                !! edges with the problem
            character(len=*), intent(in) :: one
                !! "edge ..." for one of them
            character(len=*), intent(in) :: several
                !! "edges ..." for several
            character(len=:), allocatable :: text
                !! the count in words, an open parenthesis first

            if (count == 1) then
                text = " (1 "//one
            else
                text = " ("//i8_text(int(count, i8))//" "//several
            end if
        end function how_many

        subroutine out_of_memory()
            call fatal_error(error, "out of memory checking a surface of "// &
                i8_text(int(mesh%n, i8))//" triangles: "//trim(alloc_message), exit_other)
        end subroutine out_of_memory

    end subroutine check_closed

    !> Volume enclosed by a closed surface (divergence theorem): positive when the normals point
    !> outwards, negative when the surface is inside out. Meaningful only for a closed mesh.
    pure function enclosed_volume(mesh) result(volume)
        type(stl_mesh_type), intent(in) :: mesh
            !! closed mesh (see check_closed)
        real(wp) :: volume
            !! signed enclosed volume [m3]

        real(wp) :: centre(3), a(3), b(3), c(3)
        integer :: t

        ! relative to the box centre: no cancellation for a body far from the origin
        centre = 0.5_wp*(mesh%lo + mesh%hi)
        volume = 0.0_wp
        do t = 1, mesh%n
            a = mesh%vertex(:, 1, t) - centre
            b = mesh%vertex(:, 2, t) - centre
            c = mesh%vertex(:, 3, t) - centre
            volume = volume + a(1)*(b(2)*c(3) - b(3)*c(2)) + a(2)*(b(3)*c(1) - b(1)*c(3)) &
                + a(3)*(b(1)*c(2) - b(2)*c(1))
        end do
        volume = volume/6.0_wp
    end function enclosed_volume

    !> One step of a multiplicative hash (after MurmurHash2) on values below 2**32; every
    !> intermediate stays below 2**63, so no integer overflows.
    pure integer(i8) function mix(h, value)
        integer(i8), intent(in) :: h
            !! hash so far, 0 <= h < 2**32
        integer(i8), intent(in) :: value
            !! next value, 0 <= value < 2**32

        integer(i8) :: product

        product = ieor(h, value)*1540483477_i8
        mix = iand(ieor(product, ishft(product, -29)), mask32)
    end function mix

    ! ------------------------------------------------------------------------------------------
    ! Text helpers
    ! ------------------------------------------------------------------------------------------

    !> An input error about the file: "<key> = "<path>": <reason>".
    pure subroutine refuse(error, ctx, reason)
        type(error_type), allocatable, intent(inout) :: error
            !! the error to create
        type(stl_context_type), intent(in) :: ctx
            !! file and key
        character(len=*), intent(in) :: reason
            !! what is wrong

        if (allocated(error)) deallocate (error)
        call fatal_error(error, describe_file(ctx)//": "//trim(adjustl(reason)), exit_input)
    end subroutine refuse

    !> The file as messages name it: `contact.file = "t.stl"` or `STL file "t.stl"`.
    pure function describe_file(ctx) result(text)
        type(stl_context_type), intent(in) :: ctx
            !! file and key
        character(len=:), allocatable :: text
            !! the description

        if (allocated(ctx%key)) then
            text = ctx%key//' = "'//ctx%path//'" (STL file)'
        else
            text = 'STL file "'//ctx%path//'"'
        end if
    end function describe_file

    !> A token for a message: at most 40 characters, non-printable ones shown as '?'.
    pure function shown(token, length) result(text)
        character(len=*), intent(in) :: token
            !! the token as stored
        integer, intent(in) :: length
            !! its real length (may exceed len(token))
        character(len=:), allocatable :: text
            !! printable text

        integer :: i, code

        text = token(1:min(length, 40, len(token)))
        do i = 1, len(text)
            code = iachar(text(i:i))
            if (code < 32 .or. code > 126) text(i:i) = "?"
        end do
        if (length > 40) text = text//"..."
    end function shown

    !> True when `head` looks like text: no control bytes other than whitespace.
    pure logical function is_text(head)
        character(len=*), intent(in) :: head
            !! first bytes of a file

        integer :: i, code

        is_text = .true.
        do i = 1, len(head)
            code = iachar(head(i:i))
            if ((code < 32 .and. .not. is_space(head(i:i))) .or. code == 127) then
                is_text = .false.
                return
            end if
        end do
    end function is_text

    !> Blank, tab, line feed, carriage return, vertical tab or form feed.
    elemental logical function is_space(c)
        character, intent(in) :: c
            !! one character

        is_space = c == " " .or. (iachar(c) >= 9 .and. iachar(c) <= 13)
    end function is_space

    !> A decimal digit.
    elemental logical function is_digit(c)
        character, intent(in) :: c
            !! one character

        is_digit = c >= "0" .and. c <= "9"
    end function is_digit

    !> "line 12: " before a message about an ASCII file, "" for a binary one (line 0).
    pure function line_prefix(line) result(text)
        integer, intent(in) :: line
            !! line number, 0 for none
        character(len=:), allocatable :: text
            !! the prefix

        text = ""
        if (line > 0) text = "line "//i8_text(int(line, i8))//": "
    end function line_prefix

    !> What a binary size mismatch suggests.
    pure function size_hint(short) result(text)
        logical, intent(in) :: short
            !! the file is shorter than its count needs
        character(len=:), allocatable :: text
            !! the hint, in parentheses

        if (short) then
            text = " (truncated?)"
        else
            text = " (extra bytes after the last triangle?)"
        end if
    end function size_hint

end module mpm_stl
