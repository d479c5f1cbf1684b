!> Thin binding of the cJSON C library (Debian libcjson-dev) through iso_c_binding.
!>
!> This is the only module that knows about cJSON, so the JSON library could be swapped by
!> rewriting this file alone. It offers a read-only view of a parsed document: a
!> `json_document_type` owns the tree, `json_value_type` values borrow nodes of it.
module mpm_json
    use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_int, c_double, &
        c_char, c_null_char, c_size_t, c_f_pointer, c_int16_t, c_int32_t, c_int64_t
    use, intrinsic :: ieee_exceptions, only: ieee_get_halting_mode, ieee_set_halting_mode, &
        ieee_set_flag, ieee_overflow
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_input
    use mpm_strings, only: int_text
    implicit none
    private
    public :: json_document_type, json_value_type
    public :: json_parse_file, json_parse_string, json_free, json_root
    public :: json_is_valid, json_is_object, json_is_array, json_is_number, json_is_string
    public :: json_is_bool, json_is_null, json_type_name
    public :: json_get, json_size, json_item, json_key
    public :: json_number, json_string, json_bool
    public :: max_file_bytes, max_nesting

    integer(i8), parameter :: max_file_bytes = 64_i8*1024*1024
        !! largest JSON file read [bytes] (64 MiB; a case file is a few kB)
    integer, parameter :: max_nesting = 1000
        !! deepest nesting of arrays and objects (cJSON's CJSON_NESTING_LIMIT; a case has 4)

    !> Owner of a parsed cJSON tree; free it with json_free.
    type :: json_document_type
        type(c_ptr) :: root = c_null_ptr
            !! cJSON root node, owned
    end type json_document_type

    !> A borrowed node of a document (valid while the document lives).
    type :: json_value_type
        type(c_ptr) :: ptr = c_null_ptr
            !! cJSON node, not owned
    end type json_value_type

    !> Mirror of `struct cJSON` (cJSON.h, public and stable since 1.0).
    type, bind(c) :: cjson_node
        type(c_ptr) :: next
        type(c_ptr) :: prev
        type(c_ptr) :: child
        integer(c_int) :: type
        type(c_ptr) :: valuestring
        integer(c_int) :: valueint
        real(c_double) :: valuedouble
        type(c_ptr) :: string
    end type cjson_node

    !> Mirror of `struct statx` (linux/stat.h: one layout on every architecture, unlike
    !> `struct stat`), up to the size; the kernel fills 256 bytes.
    type, bind(c) :: statx_buffer
        integer(c_int32_t) :: mask
        integer(c_int32_t) :: blksize
        integer(c_int64_t) :: attributes
        integer(c_int32_t) :: nlink
        integer(c_int32_t) :: uid
        integer(c_int32_t) :: gid
        integer(c_int16_t) :: mode
        integer(c_int16_t) :: spare
        integer(c_int64_t) :: ino
        integer(c_int64_t) :: size
        integer(c_int64_t) :: rest(26)
    end type statx_buffer

    ! statx arguments and file type bits of stx_mode (fcntl.h, sys/stat.h)
    integer(c_int), parameter :: at_fdcwd = -100_c_int
    integer(c_int32_t), parameter :: statx_type = 1_c_int32_t, statx_size = 512_c_int32_t
    integer, parameter :: s_ifmt = int(o'170000'), s_ifreg = int(o'100000'), &
        s_ifdir = int(o'040000'), s_ifchr = int(o'020000'), s_ifblk = int(o'060000'), &
        s_ififo = int(o'010000'), s_ifsock = int(o'140000')

    ! cJSON type flags (cJSON.h)
    integer(c_int), parameter :: cjson_false = 1, cjson_true = 2, cjson_nulltype = 4, &
        cjson_numbertype = 8, cjson_stringtype = 16, cjson_arraytype = 32, cjson_objecttype = 64

    ! allow(assumed-size): C strings passed to cJSON
    interface
        function cjson_parse_with_length_opts(text, length, end_ptr, require_null) &
                bind(c, name="cJSON_ParseWithLengthOpts") result(node)
            import :: c_ptr, c_size_t, c_int, c_char
            character(kind=c_char), intent(in) :: text(*)
            integer(c_size_t), value :: length
            type(c_ptr), intent(out) :: end_ptr
            integer(c_int), value :: require_null
            type(c_ptr) :: node
        end function cjson_parse_with_length_opts

        subroutine cjson_delete(node) bind(c, name="cJSON_Delete")
            import :: c_ptr
            type(c_ptr), value :: node
        end subroutine cjson_delete

        function cjson_get_error_ptr() bind(c, name="cJSON_GetErrorPtr") result(ptr)
            import :: c_ptr
            type(c_ptr) :: ptr
        end function cjson_get_error_ptr

        function c_statx(dirfd, path, flags, mask, buffer) bind(c, name="statx") &
                result(status)
            import :: c_int, c_char, c_int32_t, statx_buffer
            integer(c_int), value :: dirfd
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: flags
            integer(c_int32_t), value :: mask
            type(statx_buffer), intent(out) :: buffer
            integer(c_int) :: status
        end function c_statx

        function c_strlen(str) bind(c, name="strlen") result(n)
            import :: c_ptr, c_size_t
            type(c_ptr), value :: str
            integer(c_size_t) :: n
        end function c_strlen
    end interface

contains

    !> Read and parse a JSON file. Errors name the file and the line and column of a syntax error.
    !> Only a regular file is read (a FIFO, a device or a folder is refused before it is opened:
    !> it could block or never end), of at most max_file_bytes; a file whose size reads as 0
    !> (those of /proc) is read to its end, as far as that limit.
    subroutine json_parse_file(path, doc, error, contents)
        character(len=*), intent(in) :: path
            !! file to read
        type(json_document_type), intent(out) :: doc
            !! parsed document
        type(error_type), allocatable, intent(out) :: error
            !! set when the file is missing, unreadable, not a regular file or not valid JSON
        character(len=:), allocatable, intent(out), optional :: contents
            !! the text of the file, as read

        character(len=:), allocatable :: text, kind
        integer :: unit, stat
        integer(i8) :: nbytes
        logical :: exists
        character(len=256) :: msg

        call file_kind(path, kind, nbytes)
        if (len(kind) == 0) then
            ! statx failed: a missing file, or a system without it (then the size of inquire)
            inquire (file=path, exist=exists, size=nbytes)
            if (.not. exists) then
                call fatal_error(error, path//": file not found", exit_input)
                return
            end if
        else if (kind /= "regular file") then
            call fatal_error(error, path//": not a regular file ("//kind//"); a case file is "// &
                "a JSON text file", exit_input)
            return
        end if
        if (nbytes > max_file_bytes) then
            call fatal_error(error, path//": file too large: "//int_text(nbytes)//" bytes, at "// &
                "most "//int_text(max_file_bytes)//" (64 MiB)", exit_input)
            return
        end if
        open (newunit=unit, file=path, access="stream", form="unformatted", status="old", &
            action="read", iostat=stat, iomsg=msg)
        if (stat /= 0) then
            call fatal_error(error, path//": cannot open file: "//trim(msg), exit_input)
            return
        end if
        if (nbytes > 0) then
            allocate (character(len=nbytes) :: text)
            read (unit, iostat=stat, iomsg=msg) text
        else
            call read_to_end(unit, text, stat, msg)
        end if
        close (unit)
        if (stat /= 0) then
            call fatal_error(error, path//": cannot read file: "//trim(msg), exit_input)
            return
        end if
        if (len(text) > max_file_bytes) then
            call fatal_error(error, path//": file too large: more than "// &
                int_text(max_file_bytes)//" bytes (64 MiB)", exit_input)
            return
        end if
        call json_parse_string(text, doc, error, path)
        if (present(contents)) call move_alloc(text, contents)
    end subroutine json_parse_file

    !> The type of a file, by statx, without opening it: "regular file", "folder", "FIFO",
    !> ...; "" when statx fails (no such file, or no statx). `nbytes`: its size [bytes].
    subroutine file_kind(path, kind, nbytes)
        character(len=*), intent(in) :: path
            !! file name
        character(len=:), allocatable, intent(out) :: kind
            !! type of the file, "" when unknown
        integer(i8), intent(out) :: nbytes
            !! size [bytes], 0 when unknown

        type(statx_buffer) :: buffer
        integer :: mode

        kind = ""
        nbytes = 0
        if (c_statx(at_fdcwd, path//c_null_char, 0_c_int, ior(statx_type, statx_size), &
            buffer) /= 0) return
        nbytes = max(0_i8, int(buffer%size, i8))
        mode = iand(int(buffer%mode), 65535)
        select case (iand(mode, s_ifmt))
        case (s_ifreg)
            kind = "regular file"
        case (s_ifdir)
            kind = "a folder"
        case (s_ififo)
            kind = "a FIFO"
        case (s_ifchr)
            kind = "a character device"
        case (s_ifblk)
            kind = "a block device"
        case (s_ifsock)
            kind = "a socket"
        case default
            kind = "of an unknown type"
        end select
    end subroutine file_kind

    !> Read an open stream to its end, or to one byte past max_file_bytes (files whose size
    !> is not known beforehand, as those of /proc).
    subroutine read_to_end(unit, text, stat, msg)
        integer, intent(in) :: unit
            !! unit open for stream reading
        character(len=:), allocatable, intent(out) :: text
            !! what was read
        integer, intent(out) :: stat
            !! 0, or the iostat of a failed read
        character(len=256), intent(inout) :: msg
            !! message of a failed read

        character(len=:), allocatable :: buffer
        character :: byte
        integer :: n

        allocate (character(len=4096) :: buffer)
        n = 0
        do while (n <= max_file_bytes)
            read (unit, iostat=stat, iomsg=msg) byte
            if (is_iostat_end(stat)) then
                stat = 0
                exit
            end if
            if (stat /= 0) exit
            if (n == len(buffer)) buffer = buffer//repeat(" ", len(buffer))
            n = n + 1
            buffer(n:n) = byte
        end do
        text = buffer(1:n)
    end subroutine read_to_end

    !> Parse JSON text. `source` names the text in messages (usually the file name).
    subroutine json_parse_string(text, doc, error, source)
        character(len=*), intent(in) :: text
            !! JSON text
        type(json_document_type), intent(out) :: doc
            !! parsed document
        type(error_type), allocatable, intent(out) :: error
            !! set when the text is not valid JSON
        character(len=*), intent(in), optional :: source
            !! name of the text for messages

        type(c_ptr) :: end_ptr
        character(len=:), allocatable :: name
        integer :: offset, first
        logical :: halt_overflow

        name = "<input>"
        if (present(source)) name = source
        if (verify(text, " "//achar(9)//achar(10)//achar(13)) == 0) then
            call fatal_error(error, name//": the file is empty; a case file is one JSON object", &
                exit_input)
            return
        end if
        if (index(text, c_null_char) > 0) then
            call fatal_error(error, name//": the file contains a NUL byte; it is not a JSON text", &
                exit_input)
            return
        end if
        first = verify(text, " "//achar(9)//achar(10)//achar(13))
        if (scan(text(first:first), '{["-0123456789tfn') == 0) then
            call fatal_error(error, name//": not a JSON text: it starts with '"// &
                printable(text(first:min(len(text), first + 19)))//"'; a case file is one "// &
                "JSON object { ... }", exit_input)
            return
        end if
        ! (cJSON stops at its own limit too, but reports it as a syntax error)
        if (nesting_depth(text) > max_nesting) then
            call fatal_error(error, name//": arrays and objects nested deeper than "// &
                int_text(max_nesting)//" levels; a case file nests them 4 deep", exit_input)
            return
        end if
        call ieee_get_halting_mode(ieee_overflow, halt_overflow)
        call ieee_set_halting_mode(ieee_overflow, .false.)
        doc%root = cjson_parse_with_length_opts(text//c_null_char, &
            int(len(text) + 1, c_size_t), end_ptr, 1_c_int)
        ! numbers such as 1e999 overflow to Inf inside strtod: the reader reports them as
        ! out of range, so a build with floating-point traps must not halt here
        call ieee_set_halting_mode(ieee_overflow, halt_overflow)
        call ieee_set_flag(ieee_overflow, .false.)
        if (.not. c_associated(doc%root)) then
            ! cJSON leaves end_ptr at the position where parsing failed
            offset = error_offset(text, end_ptr)
            call fatal_error(error, name//": invalid JSON at "//position_text(text, offset)// &
                near_text(text, offset)// &
                " (check for a missing comma, quote or bracket, or a trailing comma)", exit_input)
            return
        end if
        ! cJSON ends a string at the NUL that \u0000 stands for: "a\u0000b" would read as "a"
        offset = nul_escape(text)
        if (offset >= 0) then
            call json_free(doc)
            call fatal_error(error, name//": a string holds \u0000 (a NUL character) at "// &
                position_text(text, offset)//"; no text of a case file may hold one", exit_input)
        end if
    end subroutine json_parse_string

    !> `text` with its control characters and bytes above 126 shown as "?" (for a quote of
    !> a binary file in a message).
    pure function printable(text) result(shown)
        character(len=*), intent(in) :: text
            !! text to quote
        character(len=len(text)) :: shown

        integer :: i

        shown = text
        do i = 1, len(text)
            if (iachar(text(i:i)) < 32 .or. iachar(text(i:i)) > 126) shown(i:i) = "?"
        end do
    end function printable

    !> "line L, column C" of the 0-based `offset` in `text`.
    pure function position_text(text, offset) result(where)
        character(len=*), intent(in) :: text
            !! JSON text
        integer, intent(in) :: offset
            !! 0-based offset
        character(len=:), allocatable :: where

        integer :: line, column, i

        line = 1
        column = 1
        do i = 1, min(offset, len(text))
            if (text(i:i) == new_line("a")) then
                line = line + 1
                column = 1
            else
                column = column + 1
            end if
        end do
        where = "line "//int_text(line)//", column "//int_text(column)
    end function position_text

    !> Deepest nesting of arrays and objects in a JSON text (brackets inside strings are text).
    pure integer function nesting_depth(text) result(deepest)
        character(len=*), intent(in) :: text
            !! JSON text

        integer :: depth, i
        logical :: in_string, escaped

        deepest = 0
        depth = 0
        in_string = .false.
        escaped = .false.
        do i = 1, len(text)
            if (in_string) then
                if (escaped) then
                    escaped = .false.
                else if (text(i:i) == achar(92)) then
                    escaped = .true.
                else if (text(i:i) == '"') then
                    in_string = .false.
                end if
            else
                select case (text(i:i))
                case ('"')
                    in_string = .true.
                case ("[", "{")
                    depth = depth + 1
                    deepest = max(deepest, depth)
                case ("]", "}")
                    depth = depth - 1
                case default
                    ! (values and separators do not nest)
                end select
            end if
        end do
    end function nesting_depth

    !> 0-based offset of the first escape \u0000 in a valid JSON text, -1 when none (a
    !> backslash outside strings is not valid JSON, so every escape is inside a string).
    pure integer function nul_escape(text) result(offset)
        character(len=*), intent(in) :: text
            !! valid JSON text

        character(len=*), parameter :: escape = achar(92)//"u0000"
        integer :: start, found, i

        offset = -1
        start = 1
        do
            found = index(text(start:), escape)
            if (found == 0) return
            found = start + found - 1
            ! an odd run of backslashes: the last one starts the escape ("\\u0000" is text)
            i = found
            do while (i > 1)
                if (text(i - 1:i - 1) /= achar(92)) exit
                i = i - 1
            end do
            if (mod(found - i, 2) == 0) then
                offset = found - 1
                return
            end if
            start = found + 1
        end do
    end function nul_escape

    !> Offset (0-based) of the parse error in `text`.
    function error_offset(text, end_ptr) result(offset)
        character(len=*), intent(in) :: text
        type(c_ptr), intent(in) :: end_ptr
        integer :: offset

        character(kind=c_char), pointer :: rest(:)
        integer(c_size_t) :: nrest

        offset = len(text)
        if (.not. c_associated(end_ptr)) return
        nrest = c_strlen(end_ptr)
        call c_f_pointer(end_ptr, rest, [max(nrest, 1_c_size_t)])
        offset = max(0, len(text) - int(nrest))
    end function error_offset

    !> A short quote of the text around a parse error.
    function near_text(text, offset) result(quote)
        character(len=*), intent(in) :: text
        integer, intent(in) :: offset
        character(len=:), allocatable :: quote

        integer :: first, last, i

        quote = ""
        if (offset >= len(text)) then
            quote = " (unexpected end of file)"
            return
        end if
        first = offset + 1
        last = min(len(text), first + 20)
        do i = first, last
            if (text(i:i) == new_line("a")) then
                last = i - 1
                exit
            end if
        end do
        if (last >= first) quote = ", near '"//text(first:last)//"'"
    end function near_text

    !> Release the tree owned by a document.
    subroutine json_free(doc)
        type(json_document_type), intent(inout) :: doc
            !! document to release

        if (c_associated(doc%root)) call cjson_delete(doc%root)
        doc%root = c_null_ptr
    end subroutine json_free

    !> Root value of a document.
    function json_root(doc) result(val)
        type(json_document_type), intent(in) :: doc
        type(json_value_type) :: val

        val%ptr = doc%root
    end function json_root

    function node_type(val) result(t)
        type(json_value_type), intent(in) :: val
        integer(c_int) :: t

        type(cjson_node), pointer :: node

        t = 0
        if (.not. c_associated(val%ptr)) return
        call c_f_pointer(val%ptr, node)
        t = iand(node%type, 255_c_int)
    end function node_type

    !> True when the value refers to an existing node.
    logical function json_is_valid(val)
        type(json_value_type), intent(in) :: val
        json_is_valid = c_associated(val%ptr)
    end function json_is_valid

    logical function json_is_object(val)
        type(json_value_type), intent(in) :: val
        json_is_object = node_type(val) == cjson_objecttype
    end function json_is_object

    logical function json_is_array(val)
        type(json_value_type), intent(in) :: val
        json_is_array = node_type(val) == cjson_arraytype
    end function json_is_array

    logical function json_is_number(val)
        type(json_value_type), intent(in) :: val
        json_is_number = node_type(val) == cjson_numbertype
    end function json_is_number

    logical function json_is_string(val)
        type(json_value_type), intent(in) :: val
        json_is_string = node_type(val) == cjson_stringtype
    end function json_is_string

    logical function json_is_bool(val)
        type(json_value_type), intent(in) :: val
        json_is_bool = node_type(val) == cjson_true .or. node_type(val) == cjson_false
    end function json_is_bool

    logical function json_is_null(val)
        type(json_value_type), intent(in) :: val
        json_is_null = node_type(val) == cjson_nulltype
    end function json_is_null

    !> JSON type name of a value, for messages ("object", "array", "number", ...).
    function json_type_name(val) result(name)
        type(json_value_type), intent(in) :: val
        character(len=:), allocatable :: name

        select case (node_type(val))
        case (cjson_false, cjson_true)
            name = "boolean"
        case (cjson_nulltype)
            name = "null"
        case (cjson_numbertype)
            name = "number"
        case (cjson_stringtype)
            name = "string"
        case (cjson_arraytype)
            name = "array"
        case (cjson_objecttype)
            name = "object"
        case default
            name = "missing"
        end select
    end function json_type_name

    !> Member `key` of an object (exact, case-sensitive match); invalid when absent.
    function json_get(obj, key) result(val)
        type(json_value_type), intent(in) :: obj
        character(len=*), intent(in) :: key
        type(json_value_type) :: val

        integer :: i

        val%ptr = c_null_ptr
        if (.not. json_is_object(obj)) return
        do i = 1, json_size(obj)
            if (json_key(json_item(obj, i)) == key) then
                val = json_item(obj, i)
                return
            end if
        end do
    end function json_get

    !> Number of members of an object or items of an array (0 for anything else).
    integer function json_size(val)
        type(json_value_type), intent(in) :: val

        type(cjson_node), pointer :: node
        type(c_ptr) :: p

        json_size = 0
        if (.not. (json_is_object(val) .or. json_is_array(val))) return
        call c_f_pointer(val%ptr, node)
        p = node%child
        do while (c_associated(p))
            json_size = json_size + 1
            call c_f_pointer(p, node)
            p = node%next
        end do
    end function json_size

    !> Item `i` (1-based) of an array, or member `i` of an object in file order.
    function json_item(val, i) result(item)
        type(json_value_type), intent(in) :: val
        integer, intent(in) :: i
        type(json_value_type) :: item

        type(cjson_node), pointer :: node
        type(c_ptr) :: p
        integer :: k

        item%ptr = c_null_ptr
        if (.not. (json_is_object(val) .or. json_is_array(val))) return
        call c_f_pointer(val%ptr, node)
        p = node%child
        do k = 2, i
            if (.not. c_associated(p)) return
            call c_f_pointer(p, node)
            p = node%next
        end do
        if (i >= 1) item%ptr = p
    end function json_item

    !> Name of an object member ("" for array items).
    function json_key(member) result(key)
        type(json_value_type), intent(in) :: member
        character(len=:), allocatable :: key

        type(cjson_node), pointer :: node

        key = ""
        if (.not. c_associated(member%ptr)) return
        call c_f_pointer(member%ptr, node)
        key = c_string(node%string)
    end function json_key

    !> Numeric value (NaN-free: cJSON refuses NaN and Inf literals).
    real(wp) function json_number(val)
        type(json_value_type), intent(in) :: val

        type(cjson_node), pointer :: node

        json_number = 0.0_wp
        if (.not. json_is_number(val)) return
        call c_f_pointer(val%ptr, node)
        json_number = real(node%valuedouble, wp)
    end function json_number

    !> String value ("" for non-strings).
    function json_string(val) result(str)
        type(json_value_type), intent(in) :: val
        character(len=:), allocatable :: str

        type(cjson_node), pointer :: node

        str = ""
        if (.not. json_is_string(val)) return
        call c_f_pointer(val%ptr, node)
        str = c_string(node%valuestring)
    end function json_string

    !> Boolean value (.false. for non-booleans).
    logical function json_bool(val)
        type(json_value_type), intent(in) :: val
        json_bool = node_type(val) == cjson_true
    end function json_bool

    !> Copy a NUL-terminated C string into a Fortran string.
    function c_string(ptr) result(str)
        type(c_ptr), intent(in) :: ptr
        character(len=:), allocatable :: str

        character(kind=c_char), pointer :: chars(:)
        integer :: n, i

        if (.not. c_associated(ptr)) then
            str = ""
            return
        end if
        n = int(c_strlen(ptr))
        call c_f_pointer(ptr, chars, [n])
        allocate (character(len=n) :: str)
        do i = 1, n
            str(i:i) = chars(i)
        end do
    end function c_string

end module mpm_json
