!> Thin binding of the cJSON C library (Debian libcjson-dev) through iso_c_binding.
!>
!> This is the only module that knows about cJSON, so the JSON library could be swapped by
!> rewriting this file alone. It offers a read-only view of a parsed document: a
!> `json_document_type` owns the tree, `json_value_type` values borrow nodes of it.
module mpm_json
    use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_associated, c_int, c_double, &
        c_char, c_null_char, c_size_t, c_f_pointer
    use, intrinsic :: ieee_exceptions, only: ieee_get_halting_mode, ieee_set_halting_mode, &
        ieee_set_flag, ieee_overflow
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_input
    implicit none
    private
    public :: json_document_type, json_value_type
    public :: json_parse_file, json_parse_string, json_free, json_root
    public :: json_is_valid, json_is_object, json_is_array, json_is_number, json_is_string
    public :: json_is_bool, json_is_null, json_type_name
    public :: json_get, json_size, json_item, json_key
    public :: json_number, json_string, json_bool

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

        function c_strlen(str) bind(c, name="strlen") result(n)
            import :: c_ptr, c_size_t
            type(c_ptr), value :: str
            integer(c_size_t) :: n
        end function c_strlen
    end interface

contains

    !> Read and parse a JSON file. Errors name the file and the line and column of a syntax error.
    subroutine json_parse_file(path, doc, error, contents)
        character(len=*), intent(in) :: path
            !! file to read
        type(json_document_type), intent(out) :: doc
            !! parsed document
        type(error_type), allocatable, intent(out) :: error
            !! set when the file is missing, unreadable or not valid JSON
        character(len=:), allocatable, intent(out), optional :: contents
            !! the text of the file, as read

        character(len=:), allocatable :: text
        integer :: unit, stat, nbytes
        logical :: exists
        character(len=256) :: msg

        inquire (file=path, exist=exists, size=nbytes)
        if (.not. exists) then
            call fatal_error(error, path//": file not found", exit_input)
            return
        end if
        if (nbytes < 0) nbytes = 0
        open (newunit=unit, file=path, access="stream", form="unformatted", status="old", &
            action="read", iostat=stat, iomsg=msg)
        if (stat /= 0) then
            call fatal_error(error, path//": cannot open file: "//trim(msg), exit_input)
            return
        end if
        allocate (character(len=nbytes) :: text)
        if (nbytes > 0) then
            read (unit, iostat=stat, iomsg=msg) text
            if (stat /= 0) then
                close (unit)
                call fatal_error(error, path//": cannot read file: "//trim(msg), exit_input)
                return
            end if
        end if
        close (unit)
        call json_parse_string(text, doc, error, path)
        if (present(contents)) call move_alloc(text, contents)
    end subroutine json_parse_file

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
        integer :: offset, line, column, i
        character(len=32) :: buf1, buf2
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
            write (buf1, "(i0)") line
            write (buf2, "(i0)") column
            call fatal_error(error, name//": invalid JSON at line "//trim(buf1)//", column " &
                //trim(buf2)//near_text(text, offset)// &
                " (check for a missing comma, quote or bracket, or a trailing comma)", exit_input)
        end if
    end subroutine json_parse_string

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
