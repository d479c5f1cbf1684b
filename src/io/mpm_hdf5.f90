!> Thin wrappers of the HDF5 Fortran API that return an error_type.
!>
!> Shared by the output writer (mpm_output) and the state files (mpm_state) so neither repeats
!> the create-dataspace / create-dataset / write / close sequence. Every wrapper closes every
!> handle it opens, also on failure, and names the file and the object in its message.
!> The library's own printing of its error stack is off: a failure reaches the user as that
!> one message, which says "no space left on device" when the disk is full (exit_output).
!>
!> Arrays keep their Fortran shape: a Fortran array `a(3, n)` becomes an HDF5 dataset of
!> dimensions (n, 3) as C, h5py and h5dump see it, so row i of the dataset is column i of `a`.
!> Strings are fixed-length, null-padded ASCII (h5py reads them as `bytes`).
!>
!> The reading procedures (datasets and attributes) are in the submodule mpm_hdf5_read.
module mpm_hdf5
    use, intrinsic :: iso_c_binding, only: c_ptr, c_null_ptr, c_loc, c_char, c_null_char
    use hdf5, only: hid_t, hsize_t, size_t, h5open_f, h5fcreate_f, h5fopen_f, h5fclose_f, &
        h5fis_hdf5_f, h5f_acc_trunc_f, h5f_acc_rdonly_f, h5f_acc_rdwr_f, h5gcreate_f, &
        h5gopen_f, h5gclose_f, h5screate_simple_f, h5screate_f, h5s_scalar_f, h5sclose_f, &
        h5sget_simple_extent_ndims_f, h5sget_simple_extent_dims_f, h5dcreate_f, h5dopen_f, &
        h5dclose_f, h5dwrite_f, h5dread_f, h5dget_space_f, h5acreate_f, h5aopen_f, &
        h5aclose_f, h5awrite_f, h5aread_f, h5aget_space_f, h5aget_type_f, h5aexists_f, &
        h5adelete_f, h5lexists_f, h5tcopy_f, h5tset_size_f, h5tset_strpad_f, h5tget_size_f, &
        h5tget_class_f, h5tis_variable_str_f, h5tclose_f, h5t_fortran_s1, h5t_str_nullpad_f, &
        h5t_string_f, h5kind_to_type, h5_real_kind, h5_integer_kind, h5iis_valid_f, &
        h5t_native_double, h5pcreate_f, h5pclose_f, h5p_dataset_create_f, h5pset_virtual_f, &
        h5sselect_hyperslab_f, h5s_select_set_f, h5eset_auto_f, h5dont_atexit_f
    use mpm_kinds, only: wp, i8
    use mpm_strings, only: int_text
    use mpm_error, only: error_type, fatal_error, exit_other, exit_input, exit_output
    use mpm_filesystem, only: clear_errno, last_errno, write_failure_reason
    implicit none
    private
    public :: hdf5_location_type, text_type
    public :: hdf5_initialize, hdf5_is_hdf5_file
    public :: hdf5_create_file, hdf5_open_file, hdf5_create_group, hdf5_open_group, hdf5_close
    public :: hdf5_close_after
    public :: hdf5_has_attribute, hdf5_has_link, hdf5_dataset_shape
    public :: hdf5_write_dataset, hdf5_read_dataset, hdf5_write_column_view
    public :: hdf5_write_attribute, hdf5_read_attribute

    !> An open HDF5 file or group, with the names used in messages.
    type :: hdf5_location_type
        integer(hid_t) :: id = -1
            !! HDF5 identifier of the file or group
        logical :: is_file = .false.
            !! true for a file (closed with h5fclose_f), false for a group
        character(len=:), allocatable :: file
            !! path of the file on disk, for messages
        character(len=:), allocatable :: path
            !! path of the object inside the file ("/" for the root), for messages
    end type hdf5_location_type

    !> A string of its own length (an array of these holds names of different lengths).
    type :: text_type
        character(len=:), allocatable :: text
            !! the string
    end type text_type

    !> Write a real (rank 1 to 3) or integer (rank 1) array as one contiguous dataset:
    !> `call hdf5_write_dataset(group, name, values, error [, units=] [, components=])`;
    !> `units` and `components` become string attributes of the dataset.
    interface hdf5_write_dataset
        module procedure write_real_1d, write_real_2d, write_real_3d, write_int_1d, write_i8_1d
    end interface hdf5_write_dataset

    !> Read a dataset into an allocated array whose shape the dataset must have.
    interface hdf5_read_dataset
        module subroutine read_real_1d(location, name, values, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            real(wp), intent(inout), target, contiguous :: values(:)
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_real_1d
        module subroutine read_real_2d(location, name, values, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            real(wp), intent(inout), target, contiguous :: values(:, :)
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_real_2d
        module subroutine read_real_3d(location, name, values, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            real(wp), intent(inout), target, contiguous :: values(:, :, :)
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_real_3d
        module subroutine read_int_1d(location, name, values, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            integer, intent(inout), target, contiguous :: values(:)
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_int_1d
        module subroutine read_i8_1d(location, name, values, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            integer(i8), intent(inout), target, contiguous :: values(:)
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_i8_1d
    end interface hdf5_read_dataset

    !> Write an attribute on a file or group (replacing an existing one of the same name):
    !> an integer, a real, a string, or a 1D array of integers, reals or `text_type` strings.
    interface hdf5_write_attribute
        module procedure write_attr_int, write_attr_int_1d, write_attr_real, write_attr_real_1d, &
            write_attr_string, write_attr_text_1d
    end interface hdf5_write_attribute

    !> Read an attribute of a file or group: scalars and numeric arrays must have the expected
    !> size; a string is returned allocated, a string array as an allocated `text_type` array.
    interface hdf5_read_attribute
        module subroutine read_attr_int(location, name, value, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            integer, intent(out) :: value
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_attr_int
        module subroutine read_attr_int_1d(location, name, values, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            integer, intent(inout), target, contiguous :: values(:)
                !! array of the expected size
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_attr_int_1d
        module subroutine read_attr_real(location, name, value, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            real(wp), intent(out) :: value
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_attr_real
        module subroutine read_attr_real_1d(location, name, values, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            real(wp), intent(inout), target, contiguous :: values(:)
                !! array of the expected size
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_attr_real_1d
        module subroutine read_attr_string(location, name, value, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            character(len=:), allocatable, intent(out) :: value
                !! the string, without padding
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_attr_string
        module subroutine read_attr_text_1d(location, name, values, error)
            type(hdf5_location_type), intent(in) :: location
            character(len=*), intent(in) :: name
            type(text_type), allocatable, intent(out) :: values(:)
                !! the strings, without padding
            type(error_type), allocatable, intent(out) :: error
        end subroutine read_attr_text_1d
    end interface hdf5_read_attribute

    ! A helper of the submodule that this module calls too, declared as a separate module
    ! procedure: gfortran's link-time optimisation drops a private procedure of a module
    ! that a submodule calls.
    interface
        !> Path of `name` inside the group at `path`.
        module pure function join(path, name) result(full)
            character(len=*), intent(in) :: path, name
            character(len=:), allocatable :: full
        end function join
    end interface

contains

    !> Initialise the HDF5 Fortran library unless already done (safe to call more than once).
    !>
    !> Each h5open_f call makes new copies of the Fortran datatypes without closing the
    !> previous ones, so it is called only while H5T_NATIVE_DOUBLE is not yet a valid id.
    !>
    !> The library is told not to close itself at the exit of the process (h5dont_atexit_f,
    !> before any other HDF5 call): when a file cannot be closed (a full disk), HDF5 up to
    !> 1.14.0 frees the file but keeps its id, and its exit handler then closes it again and
    !> crashes (HDF5 pull request 2291). Every file is closed by the code that opened it, so
    !> nothing is left for that handler to do. The automatic printing of the error stack is
    !> turned off: each failing call becomes one error_type message.
    subroutine hdf5_initialize(error)
        type(error_type), allocatable, intent(out) :: error
            !! set when the library cannot be initialised

        integer :: hdferr, ignored
        logical :: ready

        ! (fails, harmlessly, when called again)
        call h5dont_atexit_f(ignored)
        call h5iis_valid_f(h5t_native_double, ready, hdferr)
        if (hdferr == 0 .and. ready) return
        call h5open_f(hdferr)
        if (hdferr /= 0) then
            call fatal_error(error, "cannot initialise the HDF5 library", exit_other)
            return
        end if
        call h5eset_auto_f(0, hdferr)
        if (hdferr /= 0) call fatal_error(error, "cannot turn off the error printing of "// &
            "the HDF5 library", exit_other)
    end subroutine hdf5_initialize

    !> True when `path` is an existing HDF5 file.
    logical function hdf5_is_hdf5_file(path)
        character(len=*), intent(in) :: path
            !! file to test (must exist: HDF5 prints an error stack for a missing file)

        logical :: status
        integer :: hdferr

        call h5fis_hdf5_f(path, status, hdferr)
        hdf5_is_hdf5_file = hdferr == 0 .and. status
    end function hdf5_is_hdf5_file

    !> Create (or truncate) an HDF5 file.
    subroutine hdf5_create_file(path, file, error, shown_as)
        character(len=*), intent(in) :: path
            !! file to create
        type(hdf5_location_type), intent(out) :: file
            !! the open file (close it with hdf5_close)
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_output) when the file cannot be created
        character(len=*), intent(in), optional :: shown_as
            !! the name messages give the file (default: path), e.g. the final name of a
            !! file written as a .tmp and renamed

        integer :: hdferr
        character(len=:), allocatable :: reason

        call clear_errno()
        call h5fcreate_f(path, h5f_acc_trunc_f, file%id, hdferr)
        if (hdferr /= 0) then
            reason = write_failure_reason(path, last_errno())
            if (len(reason) == 0) reason = "missing folder or permission denied?"
            file%file = path
            if (present(shown_as)) file%file = shown_as
            call fatal_error(error, "cannot create the HDF5 file '"//file%file//"': "// &
                reason, exit_output)
            return
        end if
        file%is_file = .true.
        file%file = path
        if (present(shown_as)) file%file = shown_as
        file%path = "/"
    end subroutine hdf5_create_file

    !> Open an existing HDF5 file.
    subroutine hdf5_open_file(path, file, error, writable)
        character(len=*), intent(in) :: path
            !! file to open
        type(hdf5_location_type), intent(out) :: file
            !! the open file (close it with hdf5_close)
        type(error_type), allocatable, intent(out) :: error
            !! set (code exit_input) when the file cannot be opened
        logical, intent(in), optional :: writable
            !! open for reading and writing (default: read only)

        integer :: hdferr, mode

        mode = h5f_acc_rdonly_f
        if (present(writable)) then
            if (writable) mode = h5f_acc_rdwr_f
        end if
        call h5fopen_f(path, mode, file%id, hdferr)
        if (hdferr /= 0) then
            call fatal_error(error, "cannot open the HDF5 file '"//path//"'", exit_input)
            return
        end if
        file%is_file = .true.
        file%file = path
        file%path = "/"
    end subroutine hdf5_open_file

    !> Create a group inside a file or group.
    subroutine hdf5_create_group(parent, name, group, error)
        type(hdf5_location_type), intent(in) :: parent
            !! open file or group
        character(len=*), intent(in) :: name
            !! name of the new group
        type(hdf5_location_type), intent(out) :: group
            !! the open group (close it with hdf5_close)
        type(error_type), allocatable, intent(out) :: error
            !! set when the group cannot be created

        integer :: hdferr

        call clear_errno()
        call h5gcreate_f(parent%id, name, group%id, hdferr)
        if (hdferr /= 0) then
            call fatal_error(error, write_failure("the group '"//join(parent%path, name)// &
                "'", parent%file, last_errno()), exit_output)
            return
        end if
        group%file = parent%file
        group%path = join(parent%path, name)
    end subroutine hdf5_create_group

    !> Open an existing group of a file or group.
    subroutine hdf5_open_group(parent, name, group, error)
        type(hdf5_location_type), intent(in) :: parent
            !! open file or group
        character(len=*), intent(in) :: name
            !! name of the group
        type(hdf5_location_type), intent(out) :: group
            !! the open group (close it with hdf5_close)
        type(error_type), allocatable, intent(out) :: error
            !! set (code exit_input) when the group does not exist

        integer :: hdferr

        if (.not. hdf5_has_link(parent, name)) then
            call fatal_error(error, "'"//parent%file//"' has no group '"// &
                join(parent%path, name)//"'", exit_input)
            return
        end if
        call h5gopen_f(parent%id, name, group%id, hdferr)
        if (hdferr /= 0) then
            call fatal_error(error, "cannot open the group '"//join(parent%path, name)// &
                "' in '"//parent%file//"'", exit_input)
            return
        end if
        group%file = parent%file
        group%path = join(parent%path, name)
    end subroutine hdf5_open_group

    !> Close a file or group opened by this module.
    subroutine hdf5_close(location, error)
        type(hdf5_location_type), intent(inout) :: location
            !! file or group to close
        type(error_type), allocatable, intent(out) :: error
            !! set when HDF5 reports a failure (a file: its data may not be complete on disk)

        integer :: hdferr

        if (location%id < 0) return
        call clear_errno()
        if (location%is_file) then
            call h5fclose_f(location%id, hdferr)
        else
            call h5gclose_f(location%id, hdferr)
        end if
        location%id = -1
        if (hdferr /= 0) then
            ! (closing writes what HDF5 still holds in memory)
            call fatal_error(error, write_failure("'"//location%path//"' (closing it)", &
                location%file, last_errno()), exit_output)
        end if
    end subroutine hdf5_close

    !> Close a file or group at the end of work that may have failed: the first error wins,
    !> so a failure to close is reported only when the work itself went well.
    subroutine hdf5_close_after(location, error)
        type(hdf5_location_type), intent(inout) :: location
            !! file or group to close
        type(error_type), allocatable, intent(inout) :: error
            !! the work's error, if any; else the close's

        type(error_type), allocatable :: close_error

        call hdf5_close(location, close_error)
        if (.not. allocated(error) .and. allocated(close_error)) call move_alloc(close_error, error)
    end subroutine hdf5_close_after

    !> True when the file or group has an attribute of that name.
    logical function hdf5_has_attribute(location, name)
        type(hdf5_location_type), intent(in) :: location
            !! open file or group
        character(len=*), intent(in) :: name
            !! attribute name

        integer :: hdferr
        logical :: exists

        call h5aexists_f(location%id, name, exists, hdferr)
        hdf5_has_attribute = hdferr == 0 .and. exists
    end function hdf5_has_attribute

    !> True when the file or group has a member (dataset or group) of that name.
    !> The dimensions of a dataset, in Fortran order (those of the array it reads into);
    !> unallocated, with error set, when there is no such dataset or it cannot be read.
    subroutine hdf5_dataset_shape(location, name, dims, error)
        type(hdf5_location_type), intent(in) :: location
            !! open file or group
        character(len=*), intent(in) :: name
            !! dataset name (no '/')
        integer(i8), allocatable, intent(out) :: dims(:)
            !! its dimensions
        type(error_type), allocatable, intent(out) :: error
            !! set (code exit_input) when there is no such dataset

        integer(hid_t) :: dataset, space
        integer(hsize_t) :: file_dims(8), max_dims(8)
        integer :: hdferr, ignored, rank

        if (.not. hdf5_has_link(location, name)) then
            call fatal_error(error, "'"//location%file//"' has no dataset '" &
                //join(location%path, name)//"'", exit_input)
            return
        end if
        space = -1
        call h5dopen_f(location%id, name, dataset, hdferr)
        if (hdferr /= 0) dataset = -1
        if (hdferr == 0) call h5dget_space_f(dataset, space, hdferr)
        if (hdferr == 0) call h5sget_simple_extent_ndims_f(space, rank, hdferr)
        if (hdferr == 0 .and. (rank < 1 .or. rank > 8)) hdferr = -1
        if (hdferr == 0) then
            call h5sget_simple_extent_dims_f(space, file_dims, max_dims, hdferr)
            if (hdferr >= 0) then
                hdferr = 0
                dims = int(file_dims(1:rank), i8)
            end if
        end if
        if (space >= 0) call h5sclose_f(space, ignored)
        if (dataset >= 0) call h5dclose_f(dataset, ignored)
        if (.not. allocated(dims)) call fatal_error(error, "cannot read the shape of the " &
            //"dataset '"//join(location%path, name)//"' of '"//location%file//"'", exit_input)
    end subroutine hdf5_dataset_shape

    logical function hdf5_has_link(location, name)
        type(hdf5_location_type), intent(in) :: location
            !! open file or group
        character(len=*), intent(in) :: name
            !! member name (no '/')

        integer :: hdferr
        logical :: exists

        call h5lexists_f(location%id, name, exists, hdferr)
        hdf5_has_link = hdferr == 0 .and. exists
    end function hdf5_has_link

    ! ----------------------------------------------------------------------------------------
    ! Datasets
    ! ----------------------------------------------------------------------------------------

    subroutine write_real_1d(location, name, values, error, units, components)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(in), target, contiguous :: values(:)
        type(error_type), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: units, components

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call write_data(location, name, h5kind_to_type(wp, h5_real_kind), buffer, &
            int(shape(values), hsize_t), error, units, components)
    end subroutine write_real_1d

    subroutine write_real_2d(location, name, values, error, units, components)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(in), target, contiguous :: values(:, :)
        type(error_type), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: units, components

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call write_data(location, name, h5kind_to_type(wp, h5_real_kind), buffer, &
            int(shape(values), hsize_t), error, units, components)
    end subroutine write_real_2d

    subroutine write_real_3d(location, name, values, error, units, components)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(in), target, contiguous :: values(:, :, :)
        type(error_type), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: units, components

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call write_data(location, name, h5kind_to_type(wp, h5_real_kind), buffer, &
            int(shape(values), hsize_t), error, units, components)
    end subroutine write_real_3d

    subroutine write_int_1d(location, name, values, error, units, components)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer, intent(in), target, contiguous :: values(:)
        type(error_type), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: units, components

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call write_data(location, name, h5kind_to_type(kind(values), h5_integer_kind), buffer, &
            int(shape(values), hsize_t), error, units, components)
    end subroutine write_int_1d

    subroutine write_i8_1d(location, name, values, error, units, components)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer(i8), intent(in), target, contiguous :: values(:)
        type(error_type), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: units, components

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call write_data(location, name, h5kind_to_type(kind(values), h5_integer_kind), buffer, &
            int(shape(values), hsize_t), error, units, components)
    end subroutine write_i8_1d

    !> Create a dataset of Fortran shape `dims`, write `buffer` in one call, add attributes.
    subroutine write_data(location, name, type_id, buffer, dims, error, units, components)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer(hid_t), intent(in) :: type_id
        type(c_ptr), intent(in) :: buffer
            !! first element (c_null_ptr when the array is empty)
        integer(hsize_t), intent(in) :: dims(:)
            !! Fortran shape of the array
        type(error_type), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: units
            !! value of the "units" attribute
        character(len=*), intent(in), optional :: components
            !! value of the "components" attribute

        integer(hid_t) :: space, dataset
        integer :: hdferr, ignored, code
        character(len=:), allocatable :: where

        where = join(location%path, name)
        space = -1
        dataset = -1
        call clear_errno()
        steps: block
            call h5screate_simple_f(size(dims), dims, space, hdferr)
            if (hdferr /= 0) exit steps
            call h5dcreate_f(location%id, name, type_id, space, dataset, hdferr)
            if (hdferr /= 0) exit steps
            if (product(dims) > 0) then
                call h5dwrite_f(dataset, type_id, buffer, hdferr)
                if (hdferr /= 0) exit steps
            end if
            if (present(units)) then
                call put_string_attribute(dataset, location%file, where, "units", &
                    [text_type(units)], scalar=.true., error=error)
                if (allocated(error)) exit steps
            end if
            if (present(components)) then
                call put_string_attribute(dataset, location%file, where, "components", &
                    [text_type(components)], scalar=.true., error=error)
                if (allocated(error)) exit steps
            end if
        end block steps
        code = last_errno()
        call clear_errno()
        ! closing the dataset writes what HDF5 buffered of it: a failure there is a failure
        ! of the write
        if (dataset >= 0) call close_written(dataset, is_attribute=.false., hdferr=hdferr, &
            code=code)
        if (space >= 0) call h5sclose_f(space, ignored)
        if (allocated(error)) return
        if (hdferr /= 0) then
            call fatal_error(error, write_failure("the dataset '"//where//"'", location%file, &
                code), exit_output)
        end if
    end subroutine write_data

    !> Write a virtual dataset that shows one column of a real (n, ncolumns) dataset of the
    !> same file as an (n) dataset: readers that cannot select a column themselves (the XDMF
    !> readers of ParaView) read it as an ordinary dataset, and no value is stored twice.
    !> The view is an empty ordinary dataset when the source has no rows (HDF5 maps no empty
    !> selection).
    subroutine hdf5_write_column_view(location, name, source, column, error, units)
        type(hdf5_location_type), intent(in) :: location
            !! open file or group that receives the view
        character(len=*), intent(in) :: name
            !! name of the view
        character(len=*), intent(in) :: source
            !! absolute path of the source dataset in the same file ("/particles/stress")
        integer, intent(in) :: column
            !! column of the source shown, 1-based
        type(error_type), allocatable, intent(out) :: error
        character(len=*), intent(in), optional :: units
            !! value of the "units" attribute

        integer(hid_t) :: source_set, source_space, space, plist, dataset
        integer(hsize_t) :: dims(2), max_dims(2)
        integer :: hdferr, rank, ignored, code
        logical :: misfit
        character(len=:), allocatable :: where

        where = join(location%path, name)
        misfit = .false.
        call clear_errno()
        source_set = -1
        source_space = -1
        space = -1
        plist = -1
        dataset = -1
        steps: block
            call h5dopen_f(location%id, source, source_set, hdferr)
            if (hdferr /= 0) exit steps
            call h5dget_space_f(source_set, source_space, hdferr)
            if (hdferr /= 0) exit steps
            call h5sget_simple_extent_ndims_f(source_space, rank, hdferr)
            if (hdferr /= 0 .or. rank /= 2) then
                hdferr = -1
                misfit = .true.
                exit steps
            end if
            ! Fortran order: dims(1) columns, dims(2) rows
            call h5sget_simple_extent_dims_f(source_space, dims, max_dims, hdferr)
            if (hdferr /= 2 .or. column < 1 .or. column > dims(1)) then
                hdferr = -1
                misfit = .true.
                exit steps
            end if
            hdferr = 0
            if (dims(2) == 0) then
                call write_data(location, name, h5kind_to_type(wp, h5_real_kind), c_null_ptr, &
                    [0_hsize_t], error, units)
                exit steps
            end if
            call h5sselect_hyperslab_f(source_space, h5s_select_set_f, &
                [int(column - 1, hsize_t), 0_hsize_t], [1_hsize_t, dims(2)], hdferr)
            if (hdferr /= 0) exit steps
            call h5screate_simple_f(1, dims(2:2), space, hdferr)
            if (hdferr /= 0) exit steps
            call h5pcreate_f(h5p_dataset_create_f, plist, hdferr)
            if (hdferr /= 0) exit steps
            ! "." is the file of the view itself
            call h5pset_virtual_f(plist, space, ".", source, source_space, hdferr)
            if (hdferr /= 0) exit steps
            call h5dcreate_f(location%id, name, h5kind_to_type(wp, h5_real_kind), space, &
                dataset, hdferr, dcpl_id=plist)
            if (hdferr /= 0) exit steps
            if (present(units)) then
                call put_string_attribute(dataset, location%file, where, "units", &
                    [text_type(units)], scalar=.true., error=error)
            end if
        end block steps
        code = last_errno()
        call clear_errno()
        ! (closing the view writes what HDF5 buffered of it, as in write_data)
        if (dataset >= 0) call close_written(dataset, is_attribute=.false., hdferr=hdferr, &
            code=code)
        if (plist >= 0) call h5pclose_f(plist, ignored)
        if (space >= 0) call h5sclose_f(space, ignored)
        if (source_space >= 0) call h5sclose_f(source_space, ignored)
        if (source_set >= 0) call h5dclose_f(source_set, ignored)
        if (allocated(error)) return
        if (misfit) then
            call fatal_error(error, "cannot write the view '"//where//"' of column "// &
                int_text(column)//" of '"//source//"' to '"//location%file//"': the "// &
                "source is not a table with that column", exit_other)
        else if (hdferr /= 0) then
            call fatal_error(error, write_failure("the view '"//where//"' of column "// &
                int_text(column)//" of '"//source//"'", location%file, code), exit_output)
        end if
    end subroutine hdf5_write_column_view

    ! ----------------------------------------------------------------------------------------
    ! Attributes
    ! ----------------------------------------------------------------------------------------

    subroutine write_attr_int(location, name, value, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer, intent(in) :: value
        type(error_type), allocatable, intent(out) :: error

        integer, target :: buffer(1)

        buffer(1) = value
        call put_attribute(location, name, h5kind_to_type(kind(value), h5_integer_kind), &
            c_loc(buffer), [integer(hsize_t) ::], error)
    end subroutine write_attr_int

    subroutine write_attr_int_1d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer, intent(in), target, contiguous :: values(:)
        type(error_type), allocatable, intent(out) :: error

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call put_attribute(location, name, h5kind_to_type(kind(values), h5_integer_kind), &
            buffer, [int(size(values), hsize_t)], error)
    end subroutine write_attr_int_1d

    subroutine write_attr_real(location, name, value, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(in) :: value
        type(error_type), allocatable, intent(out) :: error

        real(wp), target :: buffer(1)

        buffer(1) = value
        call put_attribute(location, name, h5kind_to_type(wp, h5_real_kind), c_loc(buffer), &
            [integer(hsize_t) ::], error)
    end subroutine write_attr_real

    subroutine write_attr_real_1d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        real(wp), intent(in), target, contiguous :: values(:)
        type(error_type), allocatable, intent(out) :: error

        type(c_ptr) :: buffer

        buffer = c_null_ptr
        if (size(values) > 0) buffer = c_loc(values)
        call put_attribute(location, name, h5kind_to_type(wp, h5_real_kind), buffer, &
            [int(size(values), hsize_t)], error)
    end subroutine write_attr_real_1d

    subroutine write_attr_string(location, name, value, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        character(len=*), intent(in) :: value
        type(error_type), allocatable, intent(out) :: error

        call put_string_attribute(location%id, location%file, location%path, name, &
            [text_type(value)], scalar=.true., error=error)
    end subroutine write_attr_string

    subroutine write_attr_text_1d(location, name, values, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        type(text_type), intent(in) :: values(:)
        type(error_type), allocatable, intent(out) :: error

        call put_string_attribute(location%id, location%file, location%path, name, values, &
            scalar=.false., error=error)
    end subroutine write_attr_text_1d

    !> Create (replace) a numeric attribute; `dims` empty for a scalar.
    subroutine put_attribute(location, name, type_id, buffer, dims, error)
        type(hdf5_location_type), intent(in) :: location
        character(len=*), intent(in) :: name
        integer(hid_t), intent(in) :: type_id
        type(c_ptr), intent(in) :: buffer
        integer(hsize_t), intent(in) :: dims(:)
        type(error_type), allocatable, intent(out) :: error

        integer(hid_t) :: space, attribute
        integer :: hdferr, ignored, code

        space = -1
        attribute = -1
        call clear_errno()
        steps: block
            call remove_attribute(location%id, name, hdferr)
            if (hdferr /= 0) exit steps
            if (size(dims) == 0) then
                call h5screate_f(h5s_scalar_f, space, hdferr)
            else
                call h5screate_simple_f(size(dims), dims, space, hdferr)
            end if
            if (hdferr /= 0) exit steps
            call h5acreate_f(location%id, name, type_id, space, attribute, hdferr)
            if (hdferr /= 0) exit steps
            if (product(dims) > 0) call h5awrite_f(attribute, type_id, buffer, hdferr)
        end block steps
        code = last_errno()
        call clear_errno()
        if (attribute >= 0) call close_written(attribute, is_attribute=.true., hdferr=hdferr, &
            code=code)
        if (space >= 0) call h5sclose_f(space, ignored)
        if (hdferr /= 0) then
            call fatal_error(error, write_failure("the attribute '"//name//"' of '"// &
                location%path//"'", location%file, code), exit_output)
        end if
    end subroutine put_attribute

    !> Create (replace) a fixed-length, null-padded string attribute on any object.
    subroutine put_string_attribute(object_id, file, where, name, values, scalar, error)
        integer(hid_t), intent(in) :: object_id
            !! file, group or dataset
        character(len=*), intent(in) :: file
            !! file name, for messages
        character(len=*), intent(in) :: where
            !! object path, for messages
        character(len=*), intent(in) :: name
            !! attribute name
        type(text_type), intent(in) :: values(:)
            !! strings
        logical, intent(in) :: scalar
            !! write a scalar attribute (values has one element) instead of a 1D array
        type(error_type), allocatable, intent(out) :: error

        integer(hid_t) :: space, attribute, string_type
        integer :: hdferr, ignored, i, length, code
        type(c_ptr) :: source

        ! HDF5 has no zero-size string type: an empty string is one null byte
        length = 1
        do i = 1, size(values)
            length = max(length, len(values(i)%text))
        end do
        space = -1
        attribute = -1
        string_type = -1
        call clear_errno()
        steps: block
            character(kind=c_char, len=length), target :: buffer(size(values))

            do i = 1, size(values)
                buffer(i) = repeat(c_null_char, length)
                buffer(i)(1:len(values(i)%text)) = values(i)%text
            end do
            call remove_attribute(object_id, name, hdferr)
            if (hdferr /= 0) exit steps
            call h5tcopy_f(h5t_fortran_s1, string_type, hdferr)
            if (hdferr /= 0) exit steps
            call h5tset_size_f(string_type, int(length, size_t), hdferr)
            if (hdferr /= 0) exit steps
            call h5tset_strpad_f(string_type, h5t_str_nullpad_f, hdferr)
            if (hdferr /= 0) exit steps
            if (scalar) then
                call h5screate_f(h5s_scalar_f, space, hdferr)
            else
                call h5screate_simple_f(1, [int(size(values), hsize_t)], space, hdferr)
            end if
            if (hdferr /= 0) exit steps
            call h5acreate_f(object_id, name, string_type, space, attribute, hdferr)
            if (hdferr /= 0) exit steps
            if (size(values) > 0) then
                source = c_loc(buffer)
                call h5awrite_f(attribute, string_type, source, hdferr)
            end if
        end block steps
        code = last_errno()
        call clear_errno()
        if (attribute >= 0) call close_written(attribute, is_attribute=.true., hdferr=hdferr, &
            code=code)
        if (space >= 0) call h5sclose_f(space, ignored)
        if (string_type >= 0) call h5tclose_f(string_type, ignored)
        if (hdferr /= 0) then
            call fatal_error(error, write_failure("the attribute '"//name//"' of '"//where// &
                "'", file, code), exit_output)
        end if
    end subroutine put_string_attribute

    !> Delete an attribute if it exists (HDF5 refuses to create one twice).
    subroutine remove_attribute(object_id, name, hdferr)
        integer(hid_t), intent(in) :: object_id
        character(len=*), intent(in) :: name
        integer, intent(out) :: hdferr

        logical :: exists

        call h5aexists_f(object_id, name, exists, hdferr)
        if (hdferr /= 0 .or. .not. exists) return
        call h5adelete_f(object_id, name, hdferr)
    end subroutine remove_attribute

    ! ----------------------------------------------------------------------------------------
    ! Text helpers
    ! ----------------------------------------------------------------------------------------

    !> Close a dataset or attribute that was written: the close writes what HDF5 buffered of
    !> it, so its failure is a failure of the write (kept in hdferr and code unless an earlier
    !> step already failed).
    subroutine close_written(id, is_attribute, hdferr, code)
        integer(hid_t), intent(in) :: id
            !! the open dataset or attribute
        logical, intent(in) :: is_attribute
            !! an attribute (else a dataset)
        integer, intent(inout) :: hdferr
            !! status of the write so far (0: it went well)
        integer, intent(inout) :: code
            !! errno of the failure

        integer :: status

        if (is_attribute) then
            call h5aclose_f(id, status)
        else
            call h5dclose_f(id, status)
        end if
        if (status /= 0 .and. hdferr == 0) then
            hdferr = status
            code = last_errno()
        end if
    end subroutine close_written

    !> The message of a failed write: what, into which file, and why when known ("no space
    !> left on device" for a full disk).
    function write_failure(what, file, code) result(message)
        character(len=*), intent(in) :: what
            !! the object, e.g. "the dataset '/particles/stress'"
        character(len=*), intent(in) :: file
            !! the file being written
        integer, intent(in) :: code
            !! errno after the failing call (0: unknown)
        character(len=:), allocatable :: message

        character(len=:), allocatable :: reason

        message = "cannot write "//what//" to '"//file//"'"
        reason = write_failure_reason(file, code)
        if (len(reason) > 0) message = message//": "//reason
    end function write_failure

end module mpm_hdf5
