!> Small file-system helpers on top of POSIX (libc) through iso_c_binding.
!>
!> Fortran has no standard way to create a folder or rename a file; these helpers call the C
!> library directly (mkdir, opendir, access, rename, remove) instead of a shell, so a path
!> with blanks or quotes needs no escaping. They return an error_type and never stop.
!>
!> Also here: why a write failed (`errno`, and the free space of the file system through
!> statvfs, since HDF5 keeps errno to itself), and the advisory lock a run holds on its output
!> folder (`lock_folder`: flock on `<dir>/.mpm_geo.lock`, which the kernel drops when the
!> process ends, however it ends).
module mpm_filesystem
    use, intrinsic :: iso_c_binding, only: c_char, c_int, c_long, c_size_t, c_ptr, c_null_ptr, &
        c_null_char, c_associated, c_f_pointer
    use mpm_error, only: error_type, fatal_error, exit_other, exit_input, exit_output
    implicit none
    private
    public :: make_directory, directory_exists, file_exists, rename_file, remove_file
    public :: parent_directory, c_string
    public :: clear_errno, last_errno, write_failure_reason
    public :: folder_lock_type, lock_folder, release_folder, lock_file_name
    public :: text_file_type, open_text_file, put_line, flush_text_file, close_text_file

    character(len=*), parameter :: lock_file_name = ".mpm_geo.lock"
        !! the lock file of an output folder (holds the pid and host of the run that has it)

    ! errno values of Linux (asm-generic/errno-base.h, errno.h)
    integer(c_int), parameter :: enospc = 28_c_int
    integer(c_int), parameter :: edquot = 122_c_int
    integer(c_int), parameter :: ewouldblock = 11_c_int
    ! flock(2) operations
    integer(c_int), parameter :: lock_ex = 2_c_int, lock_nb = 4_c_int

    !> The advisory lock of a run on its output folder (lock_folder). The lock is the
    !> kernel's flock on the open lock file: it ends when the file is closed (release_folder,
    !> or when the variable goes out of scope) or when the process ends, also by kill -9.
    type :: folder_lock_type
        type(c_ptr) :: stream = c_null_ptr
            !! the open lock file (C FILE *); null when no lock is held
    contains
        final :: finalize_lock
    end type folder_lock_type

    !> A text file written through the C library, so that a failed write is seen: gfortran
    !> drops the errors of its buffered writes (a formatted write, flush and close to a full
    !> disk all return iostat 0). The first failure is kept and reported by flush_text_file
    !> and close_text_file, with errno, as the C library's ferror would.
    type :: text_file_type
        type(c_ptr) :: stream = c_null_ptr
            !! the open file (C FILE *); null when closed
        character(len=:), allocatable :: path
            !! the file, for messages
        character(len=:), allocatable :: shown_as
            !! the name messages give it (the final name of a file written as a .tmp)
        integer :: failure = 0
            !! 0, or errno of the first failed write (-1: a failure without errno)
        integer(c_long) :: good_size = 0
            !! bytes of the file known to be on disk (at the last flush that succeeded)
    contains
        final :: finalize_text_file
    end type text_file_type

    !> struct statvfs of Linux on 64-bit targets (glibc and musl: eleven unsigned longs, then
    !> six ints); the padding leaves room for a larger struct of another C library.
    type, bind(c) :: statvfs_type
        integer(c_long) :: f_bsize, f_frsize, f_blocks, f_bfree, f_bavail, f_files, f_ffree, &
            f_favail, f_fsid, f_flag, f_namemax
        integer(c_int) :: spare(6)
        integer(c_long) :: padding(16)
    end type statvfs_type

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

        function c_errno_location() bind(c, name="__errno_location") result(location)
            import :: c_ptr
            type(c_ptr) :: location
        end function c_errno_location

        function c_statvfs(path, buffer) bind(c, name="statvfs") result(status)
            import :: c_char, c_int, statvfs_type
            character(kind=c_char), intent(in) :: path(*)
            type(statvfs_type), intent(out) :: buffer
            integer(c_int) :: status
        end function c_statvfs

        function c_geteuid() bind(c, name="geteuid") result(uid)
            import :: c_int
            integer(c_int) :: uid
        end function c_geteuid

        function c_getpid() bind(c, name="getpid") result(pid)
            import :: c_int
            integer(c_int) :: pid
        end function c_getpid

        function c_gethostname(name, length) bind(c, name="gethostname") result(status)
            import :: c_char, c_int, c_size_t
            character(kind=c_char), intent(out) :: name(256)
            integer(c_size_t), value :: length
            integer(c_int) :: status
        end function c_gethostname

        function c_strerror(code) bind(c, name="strerror") result(text)
            import :: c_int, c_ptr
            integer(c_int), value :: code
            type(c_ptr) :: text
        end function c_strerror

        function c_fopen(path, mode) bind(c, name="fopen") result(stream)
            import :: c_char, c_ptr
            character(kind=c_char), intent(in) :: path(*)
            character(kind=c_char), intent(in) :: mode(*)
            type(c_ptr) :: stream
        end function c_fopen

        function c_fclose(stream) bind(c, name="fclose") result(status)
            import :: c_ptr, c_int
            type(c_ptr), value :: stream
            integer(c_int) :: status
        end function c_fclose

        function c_fileno(stream) bind(c, name="fileno") result(fd)
            import :: c_ptr, c_int
            type(c_ptr), value :: stream
            integer(c_int) :: fd
        end function c_fileno

        function c_fputs(text, stream) bind(c, name="fputs") result(status)
            import :: c_char, c_ptr, c_int
            character(kind=c_char), intent(in) :: text(*)
            type(c_ptr), value :: stream
            integer(c_int) :: status
        end function c_fputs

        function c_fflush(stream) bind(c, name="fflush") result(status)
            import :: c_ptr, c_int
            type(c_ptr), value :: stream
            integer(c_int) :: status
        end function c_fflush

        function c_flock(fd, operation) bind(c, name="flock") result(status)
            import :: c_int
            integer(c_int), value :: fd, operation
            integer(c_int) :: status
        end function c_flock

        function c_ftell(stream) bind(c, name="ftell") result(offset)
            import :: c_ptr, c_long
            type(c_ptr), value :: stream
            integer(c_long) :: offset
        end function c_ftell

        function c_truncate(path, length) bind(c, name="truncate") result(status)
            import :: c_char, c_int, c_long
            character(kind=c_char), intent(in) :: path(*)
            integer(c_long), value :: length
            integer(c_int) :: status
        end function c_truncate

        function c_ftruncate(fd, length) bind(c, name="ftruncate") result(status)
            import :: c_int, c_long
            integer(c_int), value :: fd
            integer(c_long), value :: length
            integer(c_int) :: status
        end function c_ftruncate
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

    !> Set errno to 0, so that the errno after a failing call is that call's.
    subroutine clear_errno()
        integer(c_int), pointer :: errno

        call c_f_pointer(c_errno_location(), errno)
        errno = 0_c_int
    end subroutine clear_errno

    !> The C library's errno now (0 when no call failed since clear_errno).
    integer function last_errno()
        integer(c_int), pointer :: errno

        call c_f_pointer(c_errno_location(), errno)
        last_errno = int(errno)
    end function last_errno

    !> Why a write into `path` failed, for a message: "no space left on device" when errno
    !> says so or when the file system of the file has no free block left for this process
    !> (a library such as HDF5 may have made other calls since the failing write); else the
    !> C library's text for errno; "" when nothing is known.
    function write_failure_reason(path, code) result(reason)
        character(len=*), intent(in) :: path
            !! the file that could not be written
        integer, intent(in) :: code
            !! errno right after the failure (0: unknown)
        character(len=:), allocatable :: reason

        character(kind=c_char), pointer :: text(:)
        character(len=:), allocatable :: folder
        type(statvfs_type) :: fs
        integer :: n
        logical :: full

        if (code == enospc) then
            reason = "no space left on device"
            return
        else if (code == edquot) then
            reason = "disk quota exceeded"
            return
        end if
        folder = parent_directory(path)
        if (len(folder) == 0) folder = "."
        full = .false.
        if (c_statvfs(c_string(folder), fs) == 0) then
            ! root may write into the blocks kept for it, other users not
            if (c_geteuid() == 0_c_int) then
                full = fs%f_bfree == 0
            else
                full = fs%f_bavail == 0
            end if
        end if
        if (full) then
            reason = "no space left on device"
        else if (code /= 0) then
            call c_f_pointer(c_strerror(int(code, c_int)), text, [4096])
            n = 0
            do while (n < size(text))
                if (text(n + 1) == c_null_char) exit
                n = n + 1
            end do
            allocate (character(len=n) :: reason)
            reason = transfer(text(1:n), reason)
            if (n > 0) then
                ! "Permission denied" -> "permission denied", as the rest of the message
                if (reason(1:1) >= "A" .and. reason(1:1) <= "Z") reason(1:1) = &
                    achar(iachar(reason(1:1)) + 32)
            end if
        else
            reason = ""
        end if
    end function write_failure_reason

    !> Take the advisory lock of an output folder (which must exist): an exclusive flock on
    !> `<dir>/.mpm_geo.lock`, which then holds the pid and the host name of this process.
    !> A folder another process holds is refused with exit_input, naming that process.
    subroutine lock_folder(dir, lock, error)
        character(len=*), intent(in) :: dir
            !! the output folder
        type(folder_lock_type), intent(inout) :: lock
            !! the lock, held until release_folder (or the end of the process)
        type(error_type), allocatable, intent(out) :: error
            !! set when another run holds the folder or the lock file cannot be made

        character(len=:), allocatable :: path
        character(kind=c_char) :: host(256)
        character(len=32) :: pid
        integer(c_int) :: fd, code, status
        integer :: n

        call release_folder(lock)
        path = dir//"/"//lock_file_name
        call clear_errno()
        ! "a+": create the file if need be, never truncate another run's record
        lock%stream = c_fopen(c_string(path), c_string("a+"))
        if (.not. c_associated(lock%stream)) then
            call fatal_error(error, "cannot create the lock file '"//path//"' of the output "// &
                "folder: "//write_failure_reason(path, last_errno()), exit_output)
            return
        end if
        fd = c_fileno(lock%stream)
        call clear_errno()
        if (c_flock(fd, ior(lock_ex, lock_nb)) /= 0) then
            code = int(last_errno(), c_int)
            ! (closed, not released: the record in the file is the holder's)
            status = c_fclose(lock%stream)
            lock%stream = c_null_ptr
            if (code == ewouldblock) then
                call fatal_error(error, "output folder '"//dir//"' is in use by another run ("// &
                    holder(path)//"); wait for it to finish or choose another --output", &
                    exit_input)
            else
                call fatal_error(error, "cannot lock the output folder '"//dir//"' ("//path// &
                    "): "//write_failure_reason(path, int(code)), exit_other)
            end if
            return
        end if
        host = c_null_char
        if (c_gethostname(host, int(size(host) - 1, c_size_t)) /= 0) host = c_null_char
        n = 0
        do while (n < size(host))
            if (host(n + 1) == c_null_char) exit
            n = n + 1
        end do
        write (pid, "(i0)") c_getpid()
        ! a record of this run for the message of another; the lock does not depend on it
        if (c_ftruncate(fd, 0_c_long) == 0) then
            if (c_fputs(c_string(trim(pid)//" "//transfer(host(1:n), repeat(" ", n))// &
                new_line("a")), lock%stream) >= 0) code = c_fflush(lock%stream)
        end if

    contains

        !> "pid N on host H" from the lock file of the process that holds it.
        function holder(file) result(text)
            character(len=*), intent(in) :: file
            character(len=:), allocatable :: text

            character(len=512) :: line
            character(len=64) :: holder_pid
            character(len=256) :: msg
            integer :: unit, stat, blank

            text = "pid unknown: the lock file holds no record yet"
            open (newunit=unit, file=file, status="old", action="read", iostat=stat, iomsg=msg)
            if (stat /= 0) return
            read (unit, "(a)", iostat=stat, iomsg=msg) line
            close (unit)
            if (stat /= 0 .or. len_trim(line) == 0) return
            line = adjustl(line)
            blank = index(trim(line), " ")
            if (blank == 0) then
                text = "pid "//trim(line)
            else
                holder_pid = line(1:blank - 1)
                text = "pid "//trim(holder_pid)//" on host "//trim(adjustl(line(blank + 1:)))
            end if
        end function holder

    end subroutine lock_folder

    !> Give the lock of an output folder back (nothing when none is held). The lock file
    !> stays, empty: deleting it could let two runs lock two different files of one name.
    subroutine release_folder(lock)
        type(folder_lock_type), intent(inout) :: lock
            !! the lock to release

        integer(c_int) :: status

        if (.not. c_associated(lock%stream)) return
        status = c_ftruncate(c_fileno(lock%stream), 0_c_long)
        status = c_fclose(lock%stream)
        lock%stream = c_null_ptr
    end subroutine release_folder

    !> A lock that goes out of scope is released.
    subroutine finalize_lock(lock)
        type(folder_lock_type), intent(inout) :: lock

        call release_folder(lock)
    end subroutine finalize_lock

    !> Open a text file for writing: a new (emptied) file, or the end of an existing one.
    subroutine open_text_file(path, file, error, append, shown_as)
        character(len=*), intent(in) :: path
            !! the file
        type(text_file_type), intent(inout) :: file
            !! the open file (close it with close_text_file)
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_output) when the file cannot be opened
        logical, intent(in), optional :: append
            !! write at the end of an existing file (default: replace it)
        character(len=*), intent(in), optional :: shown_as
            !! the name messages give the file (default: path)

        character(len=1) :: mode
        integer :: bytes

        call discard_text_file(file)
        mode = "w"
        if (present(append)) then
            if (append) mode = "a"
        end if
        file%path = path
        file%shown_as = path
        if (present(shown_as)) file%shown_as = shown_as
        file%failure = 0
        file%good_size = 0
        if (mode == "a") then
            inquire (file=path, size=bytes)
            file%good_size = max(bytes, 0)
        end if
        call clear_errno()
        file%stream = c_fopen(c_string(path), c_string(mode))
        if (.not. c_associated(file%stream)) then
            call fatal_error(error, text_failure(file, last_errno()), exit_output)
        end if
    end subroutine open_text_file

    !> Write one line (and its newline); a failure is kept for flush_text_file.
    subroutine put_line(file, line)
        type(text_file_type), intent(inout) :: file
            !! an open file
        character(len=*), intent(in) :: line
            !! the line, without its newline

        if (.not. c_associated(file%stream) .or. file%failure /= 0) return
        call clear_errno()
        if (c_fputs(c_string(line//new_line("a")), file%stream) < 0) call note_failure(file)
    end subroutine put_line

    !> Write what is buffered to the file; report the first failure of the writes so far.
    subroutine flush_text_file(file, error)
        type(text_file_type), intent(inout) :: file
            !! an open file
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_output) when a write failed; the message names the file and why

        if (.not. c_associated(file%stream)) then
            if (file%failure /= 0) call fatal_error(error, text_failure(file, file%failure), &
                exit_output)
            return
        end if
        if (file%failure == 0) then
            call clear_errno()
            if (c_fflush(file%stream) /= 0) then
                call note_failure(file)
            else
                file%good_size = c_ftell(file%stream)
            end if
        end if
        if (file%failure /= 0) then
            call cut_to_good_size(file)
            call fatal_error(error, text_failure(file, file%failure), exit_output)
        end if
    end subroutine flush_text_file

    !> After a failed write: close the file and cut it back to what the last good flush
    !> left, so that it ends with a whole line (a history stays readable).
    subroutine cut_to_good_size(file)
        type(text_file_type), intent(inout) :: file

        integer(c_int) :: status

        call discard_text_file(file)
        status = c_truncate(c_string(file%path), file%good_size)
    end subroutine cut_to_good_size

    !> Close a text file; report the first failure of its writes (closing writes the rest).
    subroutine close_text_file(file, error)
        type(text_file_type), intent(inout) :: file
            !! the file (nothing happens when it is not open)
        type(error_type), allocatable, intent(out) :: error
            !! set (exit_output) when a write failed

        integer(c_int) :: status

        if (.not. c_associated(file%stream)) then
            if (file%failure /= 0) call fatal_error(error, text_failure(file, file%failure), &
                exit_output)
            return
        end if
        if (file%failure == 0) then
            ! (the flush first: after a failed one the file is cut back before it is closed)
            call flush_text_file(file, error)
            if (allocated(error)) return
        end if
        call clear_errno()
        status = c_fclose(file%stream)
        file%stream = c_null_ptr
        if (status /= 0 .and. file%failure == 0) call note_failure(file)
        if (file%failure /= 0) then
            call cut_to_good_size(file)
            call fatal_error(error, text_failure(file, file%failure), exit_output)
        end if
    end subroutine close_text_file

    subroutine note_failure(file)
        type(text_file_type), intent(inout) :: file

        file%failure = last_errno()
        if (file%failure == 0) file%failure = -1
    end subroutine note_failure

    function text_failure(file, code) result(message)
        type(text_file_type), intent(in) :: file
        integer, intent(in) :: code
        character(len=:), allocatable :: message

        character(len=:), allocatable :: reason

        message = "cannot write '"//file%shown_as//"'"
        reason = write_failure_reason(file%path, max(code, 0))
        if (len(reason) > 0) message = message//": "//reason
    end function text_failure

    !> Close without a report (a file left open by a return on another error).
    subroutine discard_text_file(file)
        type(text_file_type), intent(inout) :: file

        integer(c_int) :: status

        if (.not. c_associated(file%stream)) return
        status = c_fclose(file%stream)
        file%stream = c_null_ptr
    end subroutine discard_text_file

    subroutine finalize_text_file(file)
        type(text_file_type), intent(inout) :: file

        call discard_text_file(file)
    end subroutine finalize_text_file

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
