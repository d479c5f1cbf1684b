!> Small file-system helpers on top of POSIX (libc) through iso_c_binding.
!>
!> Fortran has no standard way to create a folder or rename a file; these helpers call the C
!> library directly (mkdir, opendir, access, rename, remove) instead of a shell, so a path
!> with blanks or quotes needs no escaping. They return an error_type and never stop.
module mpm_filesystem
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_ptr, c_null_char, c_associated
    use mpm_error, only: error_type, fatal_error, exit_other
    implicit none
    private
    public :: make_directory, directory_exists, file_exists, rename_file, remove_file
    public :: parent_directory, c_string

    ! access(2) mode: test for existence only
    integer(c_int), parameter :: f_ok = 0_c_int
    ! mkdir(2) permission bits 0777, reduced by the process umask
    integer(c_int), parameter :: mode_rwx_all = 511_c_int

    ! allow(assumed-size): null-terminated C strings passed to libc
    interface
        function c_mkdir(path, mode) bind(c, name="mkdir") result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode
            integer(c_int) :: status
        end function c_mkdir

        function c_opendir(path) bind(c, name="opendir") result(dir)
            import :: c_char, c_ptr
            character(kind=c_char), intent(in) :: path(*)
            type(c_ptr) :: dir
        end function c_opendir

        function c_closedir(dir) bind(c, name="closedir") result(status)
            import :: c_ptr, c_int
            type(c_ptr), value :: dir
            integer(c_int) :: status
        end function c_closedir

        function c_access(path, mode) bind(c, name="access") result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int), value :: mode
            integer(c_int) :: status
        end function c_access

        function c_rename(from, to) bind(c, name="rename") result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: from(*)
            character(kind=c_char), intent(in) :: to(*)
            integer(c_int) :: status
        end function c_rename

        function c_remove(path) bind(c, name="remove") result(status)
            import :: c_char, c_int
            character(kind=c_char), intent(in) :: path(*)
            integer(c_int) :: status
        end function c_remove
    end interface

contains

    !> True when `path` names an existing folder (or a link to one).
    logical function directory_exists(path)
        character(len=*), intent(in) :: path
            !! folder path, absolute or relative to the working folder

        type(c_ptr) :: dir
        integer(c_int) :: status

        directory_exists = .false.
        if (len(path) == 0) return
        dir = c_opendir(c_string(path))
        if (c_associated(dir)) then
            directory_exists = .true.
            status = c_closedir(dir)
        end if
    end function directory_exists

    !> True when `path` exists and is not a folder (a regular file, a link to one, a device).
    logical function file_exists(path)
        character(len=*), intent(in) :: path
            !! file path, absolute or relative to the working folder

        file_exists = .false.
        if (len(path) == 0) return
        file_exists = c_access(c_string(path), f_ok) == 0
        if (file_exists) file_exists = .not. directory_exists(path)
    end function file_exists

    !> Create a folder and any missing parents (like `mkdir -p`); an existing folder is fine.
    subroutine make_directory(path, error)
        character(len=*), intent(in) :: path
            !! folder to create, absolute or relative to the working folder
        type(error_type), allocatable, intent(out) :: error
            !! set when a component cannot be created or exists as a file

        integer :: i

        if (len_trim(path) == 0) then
            call fatal_error(error, "cannot create a folder with an empty name", exit_other)
            return
        end if
        ! Every prefix that ends before a '/' is a parent to create first.
        do i = 2, len(path)
            if (path(i:i) == "/" .and. path(i - 1:i - 1) /= "/") then
                call make_one(path(1:i - 1), error)
                if (allocated(error)) return
            end if
        end do
        call make_one(path, error)

    contains

        subroutine make_one(folder, error)
            character(len=*), intent(in) :: folder
            type(error_type), allocatable, intent(out) :: error

            integer(c_int) :: status

            if (directory_exists(folder)) return
            if (file_exists(folder)) then
                call fatal_error(error, "cannot create the folder '"//path//"': '"//folder// &
                    "' exists and is not a folder", exit_other)
                return
            end if
            status = c_mkdir(c_string(folder), mode_rwx_all)
            ! Another process may have created it in between: only the result matters.
            if (.not. directory_exists(folder)) then
                call fatal_error(error, "cannot create the folder '"//folder// &
                    "' (permission denied or read-only file system?)", exit_other)
            end if
        end subroutine make_one

    end subroutine make_directory

    !> Rename (move) a file, replacing `to` if it exists; atomic within one file system.
    subroutine rename_file(from, to, error)
        character(len=*), intent(in) :: from
            !! existing file
        character(len=*), intent(in) :: to
            !! new name (an existing file of that name is replaced)
        type(error_type), allocatable, intent(out) :: error
            !! set when the rename fails

        if (c_rename(c_string(from), c_string(to)) /= 0) then
            if (.not. file_exists(from)) then
                call fatal_error(error, "cannot rename '"//from//"' to '"//to// &
                    "': '"//from//"' does not exist", exit_other)
            else
                call fatal_error(error, "cannot rename '"//from//"' to '"//to// &
                    "' (missing folder, permission denied or different file system?)", exit_other)
            end if
        end if
    end subroutine rename_file

    !> Delete a file; a file that does not exist is not an error.
    subroutine remove_file(path, error)
        character(len=*), intent(in) :: path
            !! file to delete
        type(error_type), allocatable, intent(out) :: error
            !! set when the file exists and cannot be deleted

        integer(c_int) :: status

        if (.not. file_exists(path)) return
        status = c_remove(c_string(path))
        if (status /= 0) then
            call fatal_error(error, "cannot delete the file '"//path//"'", exit_other)
        end if
    end subroutine remove_file

    !> The folder part of a path: "a/b/c.h5" -> "a/b", "/c.h5" -> "/", "c.h5" -> "".
    pure function parent_directory(path) result(parent)
        character(len=*), intent(in) :: path
            !! file or folder path
        character(len=:), allocatable :: parent
            !! everything before the last '/', without trailing '/' ("" when there is none)

        integer :: i

        i = index(path, "/", back=.true.)
        if (i == 0) then
            parent = ""
            return
        end if
        do while (i > 1)
            if (path(i - 1:i - 1) /= "/") exit
            i = i - 1
        end do
        if (i == 1) then
            parent = "/"
        else
            parent = path(1:i - 1)
        end if
    end function parent_directory

    !> A Fortran string as a null-terminated C string.
    pure function c_string(text) result(c_text)
        character(len=*), intent(in) :: text
        character(kind=c_char) :: c_text(len(text) + 1)

        integer :: i

        do i = 1, len(text)
            c_text(i) = text(i:i)
        end do
        c_text(len(text) + 1) = c_null_char
    end function c_string

end module mpm_filesystem
