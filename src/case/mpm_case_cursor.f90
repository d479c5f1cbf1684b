!> A place in a case file: a JSON object, its key path and the file name, and the typed
!> getters that read its keys.
!>
!> Every key is read through a few getters (`get_real`, `get_int`, `get_vector`,
!> `get_string`, `get_path`, `get_choice`, `get_bool`, `get_section`) that write the
!> messages, so a missing key, a wrong type and an out-of-range value are reported the same
!> way everywhere: the key path, what was found and what is allowed. Every object is checked
!> by `check_keys` for unknown keys (with the nearest allowed key) and duplicate keys before
!> its values are read. Every message starts with the case file name (code exit_input).
module mpm_case_cursor
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_input
    use mpm_strings, only: lower, path_problem, max_name_bytes, int_text, fmt_real, quoted_list, &
        plain_list, join, same, levenshtein, any_same
    use mpm_json, only: json_value_type, json_is_valid, json_type_name, json_get, json_size, &
        json_item, json_key, json_number, json_string, json_bool
    implicit none
    private
    public :: cursor_type, new_cursor, input_error, describe
    public :: room_written, room_folder

    integer, parameter :: room_written = len(".tmp")
        !! bytes added to a file the run writes (through a .tmp file and a rename)
    integer, parameter :: room_folder = 1 + max_name_bytes
        !! bytes added to the output folder: "/" and a file name

    !> A JSON value of the case file with its key path and the file name, which every message
    !> names.
    type :: cursor_type
        type(json_value_type) :: obj
            !! the value (an object for the getters, an array for `item`)
        character(len=:), allocatable :: path
            !! its key path ("" at the top level, "domain.boundaries", "materials[2]")
        character(len=:), allocatable :: src
            !! case file name, first word of every message
    contains
        !> Whether the object holds `key`.
        procedure :: has => cursor_has
        !> Key path of a key of the object.
        procedure :: key_path => cursor_key_path
        !> An input error whose message starts with the case file name.
        procedure :: fail => cursor_fail
        !> The value of `key` with its path, unchecked.
        procedure :: child => cursor_child
        !> Item i of an array, with its path "path[i]".
        procedure :: item => cursor_item
        !> Number of members of an object or items of an array.
        procedure :: size => cursor_size
        !> Whether the value is there (a key that was not given is not).
        procedure :: given => cursor_given
        !> Its JSON type, as json_type_name spells it ("object", "string", ...).
        procedure :: kind => cursor_kind
        !> The text of a string value ("" for any other).
        procedure :: text => cursor_text
        !> What the value is, for messages: 'a string ("abc")', "a number (2)", ...
        procedure :: found => cursor_found
        !> Check the JSON type of the value itself.
        procedure :: check_type => cursor_check_type
        !> Refuse unknown keys (with the nearest allowed key) and duplicate keys.
        procedure :: check_keys => cursor_check_keys
        !> Check that the value is an object with only allowed keys.
        procedure :: check_object => cursor_check_object
        !> Look a key up and check its JSON type.
        procedure :: get_typed => cursor_get_typed
        !> An optional or required object, its keys checked.
        procedure :: get_section => cursor_get_section
        !> A required, non-empty array of objects.
        procedure :: get_list => cursor_get_list
        !> Item i of an array of objects, its keys checked and its name read.
        procedure :: named_item => cursor_named_item
        !> A real number, optionally bounded.
        procedure :: get_real => cursor_get_real
        !> A whole number in a range.
        procedure :: get_int => cursor_get_int
        !> An array of one number per axis.
        procedure :: get_vector => cursor_get_vector
        !> An array of points, each an array of one number per axis.
        procedure :: get_points => cursor_get_points
        !> A non-empty string.
        procedure :: get_string => cursor_get_string
        !> A file or folder name the system takes.
        procedure :: get_path => cursor_get_path
        !> A boolean.
        procedure :: get_bool => cursor_get_bool
        !> One of a list of names, as its code.
        procedure :: get_choice => cursor_get_choice
    end type cursor_type

contains

    !> A cursor on a value of the case file.
    pure function new_cursor(obj, path, src) result(cur)
        type(json_value_type), intent(in) :: obj
            !! the value
        character(len=*), intent(in) :: path
            !! its key path ("" at the top level)
        character(len=*), intent(in) :: src
            !! case file name for messages
        type(cursor_type) :: cur
            !! the cursor

        cur%obj = obj
        cur%path = path
        cur%src = src
    end function new_cursor

    !> Create an input error whose message starts with the case file name.
    pure subroutine input_error(error, src, message)
        type(error_type), allocatable, intent(out) :: error
            !! error to create
        character(len=*), intent(in) :: src
            !! case file name
        character(len=*), intent(in) :: message
            !! what is wrong and what is allowed

        call fatal_error(error, src//": "//message, exit_input)
    end subroutine input_error

    logical function cursor_has(cur, key)
        class(cursor_type), intent(in) :: cur
            !! object
        character(len=*), intent(in) :: key
            !! key to find

        cursor_has = json_is_valid(json_get(cur%obj, key))
    end function cursor_has

    pure function cursor_key_path(cur, key) result(text)
        class(cursor_type), intent(in) :: cur
            !! object
        character(len=*), intent(in) :: key
            !! key of the object
        character(len=:), allocatable :: text
            !! "path.key", or "key" at the top level

        text = join(cur%path, key)
    end function cursor_key_path

    pure subroutine cursor_fail(cur, error, message)
        class(cursor_type), intent(in) :: cur
            !! where the error is
        type(error_type), allocatable, intent(out) :: error
            !! error to create
        character(len=*), intent(in) :: message
            !! what is wrong and what is allowed

        call input_error(error, cur%src, message)
    end subroutine cursor_fail

    function cursor_child(cur, key) result(child)
        class(cursor_type), intent(in) :: cur
            !! object
        character(len=*), intent(in) :: key
            !! key of the object
        type(cursor_type) :: child
            !! its value (invalid when absent) at path "path.key"

        child = new_cursor(json_get(cur%obj, key), join(cur%path, key), cur%src)
    end function cursor_child

    function cursor_item(cur, i) result(item)
        class(cursor_type), intent(in) :: cur
            !! array
        integer, intent(in) :: i
            !! item index, from 1
        type(cursor_type) :: item
            !! the item at path "path[i]"

        item = new_cursor(json_item(cur%obj, i), cur%path//"["//int_text(i)//"]", cur%src)
    end function cursor_item

    integer function cursor_size(cur)
        class(cursor_type), intent(in) :: cur
            !! object or array

        cursor_size = json_size(cur%obj)
    end function cursor_size

    !> Whether the value is there (a key that was not given is not).
    logical function cursor_given(cur)
        class(cursor_type), intent(in) :: cur
            !! any value

        cursor_given = json_is_valid(cur%obj)
    end function cursor_given

    !> The JSON type of the value, as json_type_name spells it.
    function cursor_kind(cur) result(kind)
        class(cursor_type), intent(in) :: cur
            !! any value
        character(len=:), allocatable :: kind
            !! "object", "array", "string", "number", "boolean", "null"

        kind = json_type_name(cur%obj)
    end function cursor_kind

    !> The text of a string value.
    function cursor_text(cur) result(text)
        class(cursor_type), intent(in) :: cur
            !! a string value
        character(len=:), allocatable :: text
            !! its text ("" for any other value)

        text = json_string(cur%obj)
    end function cursor_text

    !> What the value is, for messages.
    function cursor_found(cur) result(text)
        class(cursor_type), intent(in) :: cur
            !! any value
        character(len=:), allocatable :: text
            !! 'a string ("abc")', "a number (2)", "an object", ...

        text = describe(cur%obj)
    end function cursor_found

    !> Check the JSON type of the value itself.
    subroutine cursor_check_type(cur, kind, expect, error)
        class(cursor_type), intent(in) :: cur
            !! value to check
        character(len=*), intent(in) :: kind
            !! expected JSON type, as json_type_name spells it
        character(len=*), intent(in) :: expect
            !! what is allowed, for messages
        type(error_type), allocatable, intent(out) :: error
            !! set when the type differs

        if (json_type_name(cur%obj) /= kind) then
            call cur%fail(error, cur%path//" has the wrong type: expected "//expect &
                //", found "//describe(cur%obj))
        end if
    end subroutine cursor_check_type

    !> Check that the value is an object with only allowed keys, each once.
    subroutine cursor_check_object(cur, allowed, error)
        class(cursor_type), intent(in) :: cur
            !! value to check
        character(len=*), intent(in) :: allowed(:)
            !! keys the object may hold
        type(error_type), allocatable, intent(out) :: error
            !! set on a wrong type, an unknown key or a duplicate key

        call cur%check_type("object", "an object", error)
        if (allocated(error)) return
        call cur%check_keys(allowed, error)
    end subroutine cursor_check_object

    !> Refuse unknown keys (suggesting the nearest allowed key) and duplicate keys.
    !>
    !> With `owner` (objects whose keys depend on a type, like a material) the message also
    !> lists the keys of that owner, and a key of `known` (valid for another type) is named
    !> as such rather than matched to a look-alike.
    subroutine cursor_check_keys(cur, allowed, error, owner, known)
        class(cursor_type), intent(in) :: cur
            !! object to check
        character(len=*), intent(in) :: allowed(:)
            !! keys the object may hold
        type(error_type), allocatable, intent(out) :: error
            !! set on the first unknown or duplicate key
        character(len=*), intent(in), optional :: owner
            !! what the object is, for messages ("a newtonian material")
        character(len=*), intent(in), optional :: known(:)
            !! keys valid for other types of the same object (only with `owner`)

        character(len=:), allocatable :: key, where, message, keys_text
        integer :: i, j, k, best, dist, best_dist

        where = "the top level"
        if (len(cur%path) > 0) where = cur%path
        keys_text = "; the keys allowed in "//where//" are: "//plain_list(allowed)
        if (present(owner)) keys_text = "; the keys of "//owner//" are: "//plain_list(allowed)
        do i = 1, json_size(cur%obj)
            key = json_key(json_item(cur%obj, i))
            best = 0
            best_dist = huge(1)
            do k = 1, size(allowed)
                dist = levenshtein(lower(key), lower(trim(allowed(k))))
                if (same(key, trim(allowed(k)))) dist = -1
                ! a suggestion sharing no letter with the key would only mislead
                if (dist > 0 .and. dist >= max(len(key), len_trim(allowed(k)))) dist = huge(1)
                if (dist < best_dist) then
                    best = k
                    best_dist = dist
                end if
            end do
            if (best_dist >= 0) then
                message = "unknown key '"//cur%key_path(key)//"'"
                if (present(owner) .and. present(known)) then
                    if (any_same(known, key)) then
                        call cur%fail(error, message//": "//key//" is not a " &
                            //"parameter of "//owner//keys_text)
                        return
                    end if
                end if
                if (best_dist == 0) then
                    message = message//"; did you mean '"//trim(allowed(best))//"'? (keys " &
                        //"are case-sensitive)"
                else if (best_dist <= 3) then
                    message = message//"; did you mean '"//trim(allowed(best))//"'?"
                else
                    message = message//keys_text
                end if
                if (present(owner) .and. best_dist <= 3) then
                    message = message//" The keys of "//owner//" are: "//plain_list(allowed)
                end if
                call cur%fail(error, message)
                return
            end if
            do j = 1, i - 1
                if (same(json_key(json_item(cur%obj, j)), key)) then
                    call cur%fail(error, "duplicate key '"//cur%key_path(key)//"': it " &
                        //"appears more than once in "//where//"; give each key once")
                    return
                end if
            end do
        end do
    end subroutine cursor_check_keys

    !> Look `key` up and check its JSON type. A missing key is an error only when `required`;
    !> otherwise `found` is false and nothing else happens.
    subroutine cursor_get_typed(cur, key, kind, expect, val, found, error, required)
        class(cursor_type), intent(in) :: cur
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: kind
            !! expected JSON type, as json_type_name spells it
        character(len=*), intent(in) :: expect
            !! what is allowed, for messages ("a number > 0 [m]")
        type(cursor_type), intent(out) :: val
            !! the value found, at path "path.key"
        logical, intent(out) :: found
            !! whether the key is present
        type(error_type), allocatable, intent(out) :: error
            !! set for a missing required key or a wrong type
        logical, intent(in), optional :: required
            !! the key must be present (default: optional)

        val = cur%child(key)
        found = json_is_valid(val%obj)
        if (found) then
            call val%check_type(kind, expect, error)
        else if (is_true(required)) then
            call cur%fail(error, "missing required key '"//val%path//"' (" &
                //expect//")")
        end if
    end subroutine cursor_get_typed

    !> Read an optional or required object and check its keys.
    subroutine cursor_get_section(cur, key, allowed, sec, error, required, found)
        class(cursor_type), intent(in) :: cur
            !! object holding the section
        character(len=*), intent(in) :: key
            !! section key
        character(len=*), intent(in) :: allowed(:)
            !! keys the section may hold
        type(cursor_type), intent(out) :: sec
            !! the section (invalid when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the section must be present
        logical, intent(out), optional :: found
            !! whether the section is present

        logical :: is_present

        call cur%get_typed(key, "object", "an object", sec, is_present, error, required)
        if (present(found)) found = is_present
        if (allocated(error) .or. .not. is_present) return
        call sec%check_keys(allowed, error)
    end subroutine cursor_get_section

    !> Read a required, non-empty array of objects (`materials`, `bodies`).
    subroutine cursor_get_list(cur, key, what, list, error)
        class(cursor_type), intent(in) :: cur
            !! object holding the array
        character(len=*), intent(in) :: key
            !! array key
        character(len=*), intent(in) :: what
            !! what one item is, for messages ("material")
        type(cursor_type), intent(out) :: list
            !! the array
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        logical :: found

        call cur%get_typed(key, "array", "a non-empty array of "//what//" objects", list, &
            found, error, required=.true.)
        if (allocated(error)) return
        if (list%size() == 0) then
            call cur%fail(error, list%path//" is an empty array: give at least one "//what)
        end if
    end subroutine cursor_get_list

    !> Item i of an array of objects that may be named (loads, prescribed_motion): checked
    !> against its keys, its `name` read, "<prefix><i>" when absent.
    subroutine cursor_named_item(list, i, keys, prefix, item, name, error)
        class(cursor_type), intent(in) :: list
            !! the array
        integer, intent(in) :: i
            !! item number (from 1)
        character(len=*), intent(in) :: keys(:)
            !! keys an item may hold
        character(len=*), intent(in) :: prefix
            !! the default name is prefix followed by i
        type(cursor_type), intent(out) :: item
            !! the item
        character(len=:), allocatable, intent(out) :: name
            !! its name
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        item = list%item(i)
        call item%check_object(keys, error)
        if (allocated(error)) return
        name = prefix//int_text(i)
        call item%get_string("name", name, error)
    end subroutine cursor_named_item

    !> Read a real number, optionally bounded. The value is left as it is when the key is absent.
    subroutine cursor_get_real(cur, key, value, error, required, above, at_least, below, &
            at_most, unit, found)
        class(cursor_type), intent(in) :: cur
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        real(wp), intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        real(wp), intent(in), optional :: above
            !! value must be > above
        real(wp), intent(in), optional :: at_least
            !! value must be >= at_least
        real(wp), intent(in), optional :: below
            !! value must be < below
        real(wp), intent(in), optional :: at_most
            !! value must be <= at_most
        character(len=*), intent(in), optional :: unit
            !! unit shown in messages
        logical, intent(out), optional :: found
            !! whether the key is present

        type(cursor_type) :: val
        character(len=:), allocatable :: allowed
        logical :: is_present
        real(wp) :: x

        allowed = range_text(above, at_least, below, at_most, unit)
        call cur%get_typed(key, "number", "a number"//allowed, val, is_present, error, required)
        if (present(found)) found = is_present
        if (allocated(error) .or. .not. is_present) return
        call number_value(val, x, error)
        if (allocated(error)) return
        if (.not. in_range(x, above, at_least, below, at_most)) then
            call cur%fail(error, val%path//" = "//fmt_real(x)//" is out of range: must be" &
                //allowed)
            return
        end if
        value = x
    end subroutine cursor_get_real

    !> Read a whole number (2.0 is fine, 2.5 is not) in [at_least, at_most].
    subroutine cursor_get_int(cur, key, value, error, required, at_least, at_most)
        class(cursor_type), intent(in) :: cur
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        integer, intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        integer, intent(in), optional :: at_least
            !! smallest allowed value (default -huge(1))
        integer, intent(in), optional :: at_most
            !! largest allowed value (default huge(1))

        type(cursor_type) :: val
        character(len=:), allocatable :: allowed
        logical :: is_present
        real(wp) :: x, lower_bound, upper_bound

        lower_bound = -real(huge(1), wp)
        upper_bound = real(huge(1), wp)
        allowed = " an integer"
        if (present(at_least)) then
            lower_bound = real(at_least, wp)
            allowed = allowed//" >= "//int_text(at_least)
        end if
        if (present(at_most)) then
            upper_bound = real(at_most, wp)
            if (present(at_least)) allowed = allowed//" and"
            allowed = allowed//" <= "//int_text(at_most)
        end if
        call cur%get_typed(key, "number", allowed(2:), val, is_present, error, required)
        if (allocated(error) .or. .not. is_present) return
        call number_value(val, x, error)
        if (allocated(error)) return
        if (x /= aint(x)) then
            call cur%fail(error, val%path//" = "//fmt_real(x)//" is not a whole number: must be" &
                //allowed)
            return
        end if
        if (x < lower_bound .or. x > upper_bound) then
            call cur%fail(error, val%path//" = "//fmt_real(x)//" is out of range: must be" &
                //allowed)
            return
        end if
        value = int(x)
    end subroutine cursor_get_int

    !> Read an array of exactly `n` numbers (one per axis).
    subroutine cursor_get_vector(cur, key, n, values, error, required, unit)
        class(cursor_type), intent(in) :: cur
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        integer, intent(in) :: n
            !! number of components (the dimension)
        real(wp), intent(inout) :: values(:)
            !! components 1..n are set when the key is present
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        character(len=*), intent(in), optional :: unit
            !! unit shown in messages

        type(cursor_type) :: val
        character(len=:), allocatable :: expect
        logical :: is_present
        real(wp) :: x(3)

        expect = "an array of "//int_text(n)//" numbers"//range_text(unit=unit)
        call cur%get_typed(key, "array", expect, val, is_present, error, required)
        if (allocated(error) .or. .not. is_present) return
        call axis_numbers(val, n, x, error)
        if (allocated(error)) return
        values(1:n) = x(1:n)
    end subroutine cursor_get_vector

    !> The n numbers of an array of one number per axis (get_vector, get_points).
    subroutine axis_numbers(val, n, x, error)
        type(cursor_type), intent(in) :: val
            !! the array
        integer, intent(in) :: n
            !! numbers expected (the dimension)
        real(wp), intent(out) :: x(:)
            !! the numbers (1..n)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: item
        integer :: i

        if (val%size() /= n) then
            call val%fail(error, val%path//" must have "//int_text(n)//" numbers (one per " &
                //"axis, dimension = "//int_text(n)//"), found "//int_text(val%size()))
            return
        end if
        do i = 1, n
            item = val%item(i)
            call item%check_type("number", "a number", error)
            if (allocated(error)) return
            call number_value(item, x(i), error)
            if (allocated(error)) return
        end do
    end subroutine axis_numbers

    !> Read an array of points, each an array of n numbers (a polygon's vertices).
    subroutine cursor_get_points(cur, key, n, points, error, required, unit, at_least)
        class(cursor_type), intent(in) :: cur
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        integer, intent(in) :: n
            !! numbers per point (the dimension)
        real(wp), allocatable, intent(inout) :: points(:, :)
            !! (n, points) set when the key is present; unchanged otherwise
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        character(len=*), intent(in), optional :: unit
            !! unit shown in messages
        integer, intent(in), optional :: at_least
            !! fewest points allowed (default 1)

        type(cursor_type) :: val, point
        character(len=:), allocatable :: expect, one
        logical :: is_present
        integer :: j, fewest
        real(wp), allocatable :: x(:, :)

        fewest = 1
        if (present(at_least)) fewest = at_least
        one = "an array of "//int_text(n)//" numbers"//range_text(unit=unit)
        expect = "an array of at least "//int_text(fewest)//" points, each "//one
        call cur%get_typed(key, "array", expect, val, is_present, error, required)
        if (allocated(error) .or. .not. is_present) return
        if (val%size() < fewest) then
            call cur%fail(error, val%path//" has "//int_text(val%size())//" points; give at " &
                //"least "//int_text(fewest)//", each "//one)
            return
        end if
        allocate (x(n, val%size()))
        do j = 1, val%size()
            point = val%item(j)
            call point%check_type("array", one, error)
            if (allocated(error)) return
            call axis_numbers(point, n, x(:, j), error)
            if (allocated(error)) return
        end do
        call move_alloc(x, points)
    end subroutine cursor_get_points

    !> Read a non-empty string.
    subroutine cursor_get_string(cur, key, value, error, required, found)
        class(cursor_type), intent(in) :: cur
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=:), allocatable, intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        logical, intent(out), optional :: found
            !! whether the key is present

        type(cursor_type) :: val
        logical :: is_present

        call cur%get_typed(key, "string", "a non-empty string", val, is_present, error, required)
        if (present(found)) found = is_present
        if (allocated(error) .or. .not. is_present) return
        if (len(json_string(val%obj)) == 0) then
            call cur%fail(error, val%path//' = "" is not allowed: must be a non-empty string')
            return
        end if
        value = json_string(val%obj)
    end subroutine cursor_get_string

    !> Read a file or folder name: a non-empty string that the system takes as a path, with
    !> `room` bytes added by the program (path_problem).
    subroutine cursor_get_path(cur, key, room, value, error, required, found)
        class(cursor_type), intent(in) :: cur
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        integer, intent(in) :: room
            !! bytes the program adds: room_written, room_folder or 0 (a file it reads)
        character(len=:), allocatable, intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present
        logical, intent(out), optional :: found
            !! whether the key is present

        character(len=:), allocatable :: problem
        logical :: is_present

        call cur%get_string(key, value, error, required, is_present)
        if (present(found)) found = is_present
        if (allocated(error) .or. .not. is_present) return
        if (room == room_folder) then
            problem = path_problem(value, room, 0)
        else
            problem = path_problem(value, room, room)
        end if
        if (len(problem) > 0) call cur%fail(error, cur%key_path(key)//" is not a usable " &
            //"path: "//problem)
    end subroutine cursor_get_path

    !> Read a boolean.
    subroutine cursor_get_bool(cur, key, value, error)
        class(cursor_type), intent(in) :: cur
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        logical, intent(inout) :: value
            !! value read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: val
        logical :: is_present

        call cur%get_typed(key, "boolean", "true or false", val, is_present, error)
        if (allocated(error) .or. .not. is_present) return
        value = json_bool(val%obj)
    end subroutine cursor_get_bool

    !> Read one of a list of names (any letter case) and return its code.
    subroutine cursor_get_choice(cur, key, names, codes, value, error, required)
        class(cursor_type), intent(in) :: cur
            !! object holding the key
        character(len=*), intent(in) :: key
            !! key to read
        character(len=*), intent(in) :: names(:)
            !! accepted names (aliases included)
        integer, intent(in) :: codes(:)
            !! code of each name
        integer, intent(inout) :: value
            !! code of the name read (unchanged when absent)
        type(error_type), allocatable, intent(out) :: error
            !! first error found
        logical, intent(in), optional :: required
            !! the key must be present

        type(cursor_type) :: val
        character(len=:), allocatable :: name
        logical :: is_present
        integer :: i

        call cur%get_typed(key, "string", "one of "//quoted_list(names), val, is_present, &
            error, required)
        if (allocated(error) .or. .not. is_present) return
        name = json_string(val%obj)
        do i = 1, size(names)
            if (same(lower(name), lower(trim(names(i))))) then
                value = codes(i)
                return
            end if
        end do
        call cur%fail(error, val%path//' = "'//name//'" is not allowed: must be one of ' &
            //quoted_list(names))
    end subroutine cursor_get_choice

    !> Value of a number node, refusing numbers that overflow a double (1e999).
    subroutine number_value(val, x, error)
        type(cursor_type), intent(in) :: val
            !! a number node
        real(wp), intent(out) :: x
            !! the number
        type(error_type), allocatable, intent(out) :: error
            !! set when the number is not finite

        x = json_number(val%obj)
        if (.not. ieee_is_finite(x)) then
            x = 0.0_wp
            call val%fail(error, val%path//" is not a finite number (too large for double " &
                //"precision)")
        end if
    end subroutine number_value

    !> A value as messages show it: its type and, for scalars, the value.
    function describe(val) result(text)
        type(json_value_type), intent(in) :: val
            !! any value
        character(len=:), allocatable :: text
            !! 'a string ("abc")', "a number (2)", "an object", ...

        character(len=:), allocatable :: kind, str

        kind = json_type_name(val)
        if (kind == "string") then
            str = json_string(val)
            if (len(str) > 40) str = str(1:37)//"..."
            text = 'a string ("'//str//'")'
        else if (kind == "number") then
            if (ieee_is_finite(json_number(val))) then
                text = "a number ("//fmt_real(json_number(val))//")"
            else
                text = "a number"
            end if
        else if (kind == "boolean") then
            text = "a boolean ("//trim(merge("true ", "false", json_bool(val)))//")"
        else if (kind == "array" .or. kind == "object") then
            text = "an "//kind
        else
            text = kind
        end if
    end function describe

    !> Text of the bounds of a number: " > 0 [m]", " >= 0 and < 0.5", "" for none.
    pure function range_text(above, at_least, below, at_most, unit) result(text)
        real(wp), intent(in), optional :: above
            !! strict lower bound
        real(wp), intent(in), optional :: at_least
            !! lower bound
        real(wp), intent(in), optional :: below
            !! strict upper bound
        real(wp), intent(in), optional :: at_most
            !! upper bound
        character(len=*), intent(in), optional :: unit
            !! unit of the number
        character(len=:), allocatable :: text

        text = ""
        if (present(above)) text = text//" > "//fmt_real(above)
        if (present(at_least)) text = text//" >= "//fmt_real(at_least)
        if (len(text) > 0 .and. (present(below) .or. present(at_most))) text = text//" and"
        if (present(below)) text = text//" < "//fmt_real(below)
        if (present(at_most)) text = text//" <= "//fmt_real(at_most)
        if (present(unit)) text = text//" ["//unit//"]"
    end function range_text

    !> Whether x satisfies every bound given.
    pure logical function in_range(x, above, at_least, below, at_most)
        real(wp), intent(in) :: x
            !! value to test
        real(wp), intent(in), optional :: above
            !! strict lower bound
        real(wp), intent(in), optional :: at_least
            !! lower bound
        real(wp), intent(in), optional :: below
            !! strict upper bound
        real(wp), intent(in), optional :: at_most
            !! upper bound

        in_range = .true.
        if (present(above)) in_range = in_range .and. x > above
        if (present(at_least)) in_range = in_range .and. x >= at_least
        if (present(below)) in_range = in_range .and. x < below
        if (present(at_most)) in_range = in_range .and. x <= at_most
    end function in_range

    !> True when the optional flag is present and true.
    pure logical function is_true(flag)
        logical, intent(in), optional :: flag
            !! optional flag

        is_true = .false.
        if (present(flag)) is_true = flag
    end function is_true

end module mpm_case_cursor
