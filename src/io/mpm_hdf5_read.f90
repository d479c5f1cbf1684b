!> Reading of HDF5 datasets and attributes (the bodies of hdf5_read_dataset and
!> hdf5_read_attribute of mpm_hdf5): each checks that the object exists and has the shape
!> the caller expects, and names the file and the object in its message.
submodule(mpm_hdf5) mpm_hdf5_read
    implicit none

contains

    module subroutine read_real_1d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(inout), target, contiguous :: values(:)
        type(error_type), allocatable, intent(out) :: error

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call read_data(location, name, h5kind_to_type(wp, h5_real_kind), buffer, &
            int(shape(values), hsize_t), error)
    end subroutine read_real_1d

    module subroutine read_real_2d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(inout), target, contiguous :: values(:, :)
        type(error_type), allocatable, intent(out) :: error

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call read_data(location, name, h5kind_to_type(wp, h5_real_kind), buffer, &
            int(shape(values), hsize_t), error)
    end subroutine read_real_2d

    module subroutine read_real_3d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(inout), target, contiguous :: values(:, :, :)
        type(error_type), allocatable, intent(out) :: error

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call read_data(location, name, h5kind_to_type(wp, h5_real_kind), buffer, &
            int(shape(values), hsize_t), error)
    end subroutine read_real_3d

    module subroutine read_int_1d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer, intent(inout), target, contiguous :: values(:)
        type(error_type), allocatable, intent(out) :: error

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call read_data(location, name, h5kind_to_type(kind(values), h5_integer_kind), buffer, &
            int(shape(values), hsize_t), error)
    end subroutine read_int_1d

    module subroutine read_i8_1d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer(i8), intent(inout), target, contiguous :: values(:)
        type(error_type), allocatable, intent(out) :: error

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call read_data(location, name, h5kind_to_type(kind(values), h5_integer_kind), buffer, &
            int(shape(values), hsize_t), error)
    end subroutine read_i8_1d

    !> Read a whole dataset after checking that its shape is the Fortran shape `dims`.
    subroutine read_data(location, name, type_id, buffer, dims, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer(hid_t), intent(in) :: type_id
        type(c_ptr), intent(in) :: buffer
        integer(hsize_t), intent(in) :: dims(:)
        type(error_type), allocatable, intent(out) :: error

        integer(hid_t) :: space, dataset
        integer(hsize_t) :: file_dims(max(size(dims), 1)), max_dims(max(size(dims), 1))
        integer :: hdferr, ignored, rank
        type(c_ptr) :: destination
        character(len=:), allocatable :: where

        where = join(location%path, name)
        if (.not. hdf5_has_link(location, name)) then
            call fatal_error(error, "'"//location%file//"' has no dataset '"//where//"'", &
                exit_input)
            return
        end if
        space = -1
        dataset = -1
        steps: block
            call h5dopen_f(location%id, name, dataset, hdferr)
            if (hdferr /= 0) exit steps
            call h5dget_space_f(dataset, space, hdferr)
            if (hdferr /= 0) exit steps
            call h5sget_simple_extent_ndims_f(space, rank, hdferr)
            if (hdferr /= 0) exit steps
            if (rank /= size(dims)) then
                call fatal_error(error, "the dataset '"//where//"' of '"//location%file// &
                    "' has "//str(rank)//" dimensions, expected "//str(size(dims)), exit_input)
                exit steps
            end if
            call h5sget_simple_extent_dims_f(space, file_dims, max_dims, hdferr)
            if (hdferr < 0) exit steps
            hdferr = 0
            if (any(file_dims(1:rank) /= dims)) then
                call fatal_error(error, "the dataset '"//where//"' of '"//location%file// &
                    "' has dimensions ("//dims_text(file_dims(1:rank))//"), expected ("// &
                    dims_text(dims)//")", exit_input)
                exit steps
            end if
            if (product(dims) > 0) then
                ! the c_ptr interface of h5dread_f takes the pointer intent(inout)
                destination = buffer
                call h5dread_f(dataset, type_id, destination, hdferr)
            end if
        end block steps
        if (dataset >= 0) call h5dclose_f(dataset, ignored)
        if (space >= 0) call h5sclose_f(space, ignored)
        if (allocated(error)) return
        if (hdferr /= 0) then
            call fatal_error(error, "cannot read the dataset '"//where//"' of '"// &
                location%file//"'", exit_input)
        end if
    end subroutine read_data

    module subroutine read_attr_int(location, name, value, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer, intent(out) :: value
        type(error_type), allocatable, intent(out) :: error

        integer, target :: buffer(1)

        buffer = 0
        call get_attribute(location, name, h5kind_to_type(kind(value), h5_integer_kind), &
            c_loc(buffer), [integer(hsize_t) ::], error)
        value = buffer(1)
    end subroutine read_attr_int

    module subroutine read_attr_int_1d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer, intent(inout), target, contiguous :: values(:)
            !! array of the expected size
        type(error_type), allocatable, intent(out) :: error

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call get_attribute(location, name, h5kind_to_type(kind(values), h5_integer_kind), &
            buffer, [int(size(values), hsize_t)], error)
    end subroutine read_attr_int_1d

    module subroutine read_attr_real(location, name, value, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(out) :: value
        type(error_type), allocatable, intent(out) :: error

        real(wp), target :: buffer(1)

        buffer = 0.0_wp
        call get_attribute(location, name, h5kind_to_type(wp, h5_real_kind), c_loc(buffer), &
            [integer(hsize_t) ::], error)
        value = buffer(1)
    end subroutine read_attr_real

    module subroutine read_attr_real_1d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(inout), target, contiguous :: values(:)
            !! array of the expected size
        type(error_type), allocatable, intent(out) :: error

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call get_attribute(location, name, h5kind_to_type(wp, h5_real_kind), buffer, &
            [int(size(values), hsize_t)], error)
    end subroutine read_attr_real_1d

    !> Read a numeric attribute after checking its shape (`dims` empty: scalar or one value).
    subroutine get_attribute(location, name, type_id, buffer, dims, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer(hid_t), intent(in) :: type_id
        type(c_ptr), intent(in) :: buffer
        integer(hsize_t), intent(in) :: dims(:)
        type(error_type), allocatable, intent(out) :: error

        integer(hid_t) :: space, attribute
        integer(hsize_t) :: file_dims(1), max_dims(1)
        integer :: hdferr, ignored, rank
        integer(hsize_t) :: count, expected
        type(c_ptr) :: destination

        if (.not. hdf5_has_attribute(location, name)) then
            call fatal_error(error, "'"//location%file//"' has no attribute '"//name// &
                "' on '"//location%path//"'", exit_input)
            return
        end if
        expected = product(dims)
        space = -1
        attribute = -1
        steps: block
            call h5aopen_f(location%id, name, attribute, hdferr)
            if (hdferr /= 0) exit steps
            call h5aget_space_f(attribute, space, hdferr)
            if (hdferr /= 0) exit steps
            call h5sget_simple_extent_ndims_f(space, rank, hdferr)
            if (hdferr /= 0) exit steps
            count = 1
            if (rank == 1) then
                call h5sget_simple_extent_dims_f(space, file_dims, max_dims, hdferr)
                if (hdferr < 0) exit steps
                hdferr = 0
                count = file_dims(1)
            end if
            if (rank > 1 .or. count /= expected) then
                call fatal_error(error, "the attribute '"//name//"' of '"//location%path// &
                    "' in '"//location%file//"' has "//str(int(count))//" values, expected "// &
                    str(int(expected)), exit_input)
                exit steps
            end if
            if (expected > 0) then
                destination = buffer
                call h5aread_f(attribute, type_id, destination, hdferr)
            end if
        end block steps
        if (attribute >= 0) call h5aclose_f(attribute, ignored)
        if (space >= 0) call h5sclose_f(space, ignored)
        if (allocated(error)) return
        if (hdferr /= 0) then
            call fatal_error(error, "cannot read the attribute '"//name//"' of '"// &
                location%path//"' in '"//location%file//"'", exit_input)
        end if
    end subroutine get_attribute

    module subroutine read_attr_string(location, name, value, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        character(len=:), allocatable, intent(out) :: value
            !! the string, without padding
        type(error_type), allocatable, intent(out) :: error

        type(text_type), allocatable :: values(:)

        call get_string_attribute(location, name, values, error)
        if (allocated(error)) return
        if (size(values) /= 1) then
            call fatal_error(error, "the attribute '"//name//"' of '"//location%path// &
                "' in '"//location%file//"' has "//str(size(values))// &
                " strings, expected one", exit_input)
            return
        end if
        value = values(1)%text
    end subroutine read_attr_string

    module subroutine read_attr_text_1d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        type(text_type), allocatable, intent(out) :: values(:)
            !! the strings, without padding
        type(error_type), allocatable, intent(out) :: error

        call get_string_attribute(location, name, values, error)
    end subroutine read_attr_text_1d

    !> Read a fixed-length string attribute (scalar or 1D), cutting each string at its first
    !> null byte and dropping trailing blanks.
    subroutine get_string_attribute(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        type(text_type), allocatable, intent(out) :: values(:)
        type(error_type), allocatable, intent(out) :: error

        integer(hid_t) :: space, attribute, file_type, memory_type
        integer(hsize_t) :: file_dims(1), max_dims(1)
        integer(size_t) :: length
        integer :: hdferr, ignored, rank, type_class, count
        logical :: variable

        if (.not. hdf5_has_attribute(location, name)) then
            call fatal_error(error, "'"//location%file//"' has no attribute '"//name// &
                "' on '"//location%path//"'", exit_input)
            return
        end if
        space = -1
        attribute = -1
        file_type = -1
        memory_type = -1
        variable = .false.
        length = 1
        count = 0
        steps: block
            call h5aopen_f(location%id, name, attribute, hdferr)
            if (hdferr /= 0) exit steps
            call h5aget_type_f(attribute, file_type, hdferr)
            if (hdferr /= 0) exit steps
            call h5tget_class_f(file_type, type_class, hdferr)
            if (hdferr /= 0) exit steps
            if (type_class == h5t_string_f) then
                call h5tis_variable_str_f(file_type, variable, hdferr)
                if (hdferr /= 0) exit steps
            end if
            if (type_class /= h5t_string_f .or. variable) then
                call fatal_error(error, "the attribute '"//name//"' of '"//location%path// &
                    "' in '"//location%file//"' is not a fixed-length string", exit_input)
                exit steps
            end if
            call h5tget_size_f(file_type, length, hdferr)
            if (hdferr /= 0) exit steps
            call h5aget_space_f(attribute, space, hdferr)
            if (hdferr /= 0) exit steps
            call h5sget_simple_extent_ndims_f(space, rank, hdferr)
            if (hdferr /= 0) exit steps
            count = 1
            if (rank == 1) then
                call h5sget_simple_extent_dims_f(space, file_dims, max_dims, hdferr)
                if (hdferr < 0) exit steps
                hdferr = 0
                count = int(file_dims(1))
            else if (rank > 1) then
                call fatal_error(error, "the attribute '"//name//"' of '"//location%path// &
                    "' in '"//location%file//"' has more than one dimension", exit_input)
                exit steps
            end if
            call h5tcopy_f(h5t_fortran_s1, memory_type, hdferr)
            if (hdferr /= 0) exit steps
            call h5tset_size_f(memory_type, length, hdferr)
            if (hdferr /= 0) exit steps
            call h5tset_strpad_f(memory_type, h5t_str_nullpad_f, hdferr)
            if (hdferr /= 0) exit steps
            call read_strings(int(length))
        end block steps
        if (attribute >= 0) call h5aclose_f(attribute, ignored)
        if (space >= 0) call h5sclose_f(space, ignored)
        if (file_type >= 0) call h5tclose_f(file_type, ignored)
        if (memory_type >= 0) call h5tclose_f(memory_type, ignored)
        if (allocated(error)) return
        if (hdferr /= 0) then
            call fatal_error(error, "cannot read the attribute '"//name//"' of '"// &
                location%path//"' in '"//location%file//"'", exit_input)
        end if

    contains

        subroutine read_strings(width)
            integer, intent(in) :: width
                !! bytes per string

            character(kind=c_char, len=width), target :: buffer(count)
            type(c_ptr) :: destination
            integer :: i, cut

            if (count > 0) then
                ! the c_ptr interface of h5aread_f takes the pointer intent(inout)
                destination = c_loc(buffer)
                call h5aread_f(attribute, memory_type, destination, hdferr)
                if (hdferr /= 0) return
            end if
            allocate (values(count))
            do i = 1, count
                cut = index(buffer(i), c_null_char)
                if (cut == 0) cut = width + 1
                values(i)%text = trim(buffer(i)(1:cut - 1))
            end do
        end subroutine read_strings

    end subroutine get_string_attribute

    !> Dimensions as C/h5py order text: Fortran shape (3, 5) -> "5, 3".
    pure function dims_text(dims) result(text)
        integer(hsize_t), intent(in) :: dims(:)
        character(len=:), allocatable :: text

        integer :: i

        text = ""
        do i = size(dims), 1, -1
            text = text//str(int(dims(i)))
            if (i > 1) text = text//", "
        end do
    end function dims_text

    pure function str(value) result(text)
        integer, intent(in) :: value
        character(len=:), allocatable :: text

        character(len=24) :: buffer

        write (buffer, "(i0)") value
        text = trim(buffer)
    end function str

    !> Path of `name` inside the group at `path`.
    module pure function join(path, name) result(full)
        character(len=*), intent(in) :: path, name
        character(len=:), allocatable :: full

        if (path == "/") then
            full = "/"//name
        else
            full = path//"/"//name
        end if
    end function join

end submodule mpm_hdf5_read
