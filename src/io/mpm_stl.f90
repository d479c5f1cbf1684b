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
!> The mesh type and its geometry (`check_closed`, `enclosed_volume`) are in
!> mpm_surface_mesh (src/geometry/); this module only reads files.
module mpm_stl
    use, intrinsic :: iso_fortran_env, only: int16, int32, real32
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_input, exit_other
    use mpm_filesystem, only: file_exists, directory_exists
    use mpm_strings, only: lower, real_text, vector_text => reals_text, i8_text => int_text, &
        parse_real, number_invalid, number_finite, number_not_finite, number_too_large
    use mpm_surface_mesh, only: stl_mesh_type
    implicit none
    private
    public :: read_stl
    public :: stl_coordinate_limit

    real(wp), parameter :: stl_coordinate_limit = 1.0e30_wp
        !! largest |coordinate| accepted after scale and offset, so that edge lengths, areas
        !! and normals never overflow [m]

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
    character(len=*), parameter :: axis_names = "xyz"
    ! A triangle is degenerate when 2 area <= degenerate_tolerance * (longest edge)**2: the
    ! cross product of its edges is then at the level of its own round-off (a few epsilon times
    ! the product of the edge lengths), so the normal has no direction.
    real(wp), parameter :: degenerate_tolerance = 8.0_wp*epsilon(1.0_wp)

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
            if (length <= token_length) call parse_real(token(1:length), kind, value)
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
