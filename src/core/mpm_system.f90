!> Facts about the running process (Linux /proc), for summaries and benchmarks.
module mpm_system
    use mpm_kinds, only: wp, i8
    implicit none
    private
    public :: peak_memory_mb, available_memory_bytes

contains

    !> Peak resident memory of this process (VmHWM) [MB]; 0 where /proc is not available.
    real(wp) function peak_memory_mb()
        integer :: unit, stat, kb
        character(len=256) :: line, msg

        peak_memory_mb = 0.0_wp
        ! a probe: without /proc (not Linux) the figure is simply not reported
        open (newunit=unit, file="/proc/self/status", action="read", status="old", iostat=stat, &
            iomsg=msg)
        if (stat /= 0) return
        do
            read (unit, "(a)", iostat=stat, iomsg=msg) line
            if (stat /= 0) exit
            if (line(1:6) == "VmHWM:") then
                read (line(7:), *, iostat=stat, iomsg=msg) kb
                if (stat == 0) peak_memory_mb = real(kb, wp)/1024.0_wp
                exit
            end if
        end do
        close (unit)
    end function peak_memory_mb

    !> Memory this process can still take [bytes]: MemAvailable of /proc/meminfo, or less
    !> when a memory cgroup limits the process, as Slurm jobs and containers are: the
    !> smallest limit - usage of the process's own cgroup (/proc/self/cgroup) and of every
    !> cgroup above it (v2: memory.max, memory.current; v1: memory.limit_in_bytes,
    !> memory.usage_in_bytes); -1 when unknown (not Linux).
    integer(i8) function available_memory_bytes()
        integer :: unit, stat, colon
        character(len=1024) :: line
        character(len=256) :: msg

        available_memory_bytes = meminfo_bytes("MemAvailable:")
        open (newunit=unit, file="/proc/self/cgroup", action="read", status="old", &
            iostat=stat, iomsg=msg)
        if (stat /= 0) return
        do
            read (unit, "(a)", iostat=stat, iomsg=msg) line
            if (stat /= 0) exit
            ! "0::/path" (v2) or "N:memory:/path", "N:memory,other:/path" (v1)
            if (line(1:3) == "0::") then
                call walk_up("/sys/fs/cgroup", trim(line(4:)), "memory.max", "memory.current")
            else
                colon = index(line, ":")
                if (colon == 0) cycle
                if (index(line(colon + 1:), "memory") /= 1) cycle
                colon = colon + index(line(colon + 1:), ":")
                call walk_up("/sys/fs/cgroup/memory", trim(line(colon + 1:)), &
                    "memory.limit_in_bytes", "memory.usage_in_bytes")
            end if
        end do
        close (unit)

    contains

        !> Lower the figure to limit - usage of the cgroup at path and of each parent.
        subroutine walk_up(root, path, limit_file, usage_file)
            character(len=*), intent(in) :: root, path, limit_file, usage_file

            character(len=:), allocatable :: dir
            integer(i8) :: limit, used

            dir = path
            do
                limit = first_number(root//dir//"/"//limit_file)
                used = first_number(root//dir//"/"//usage_file)
                ! (v1 reports "no limit" as a huge number, v2 as "max", which reads as -1)
                if (limit > 0 .and. used >= 0 .and. limit < huge(limit)/2) then
                    if (available_memory_bytes < 0) then
                        available_memory_bytes = max(0_i8, limit - used)
                    else
                        available_memory_bytes = min(available_memory_bytes, &
                            max(0_i8, limit - used))
                    end if
                end if
                if (len(dir) <= 1) exit
                dir = dir(1:max(1, index(dir, "/", back=.true.) - 1))
                if (dir == "/") dir = ""
            end do
        end subroutine walk_up

    end function available_memory_bytes

    !> A line "Key: N kB" of /proc/meminfo in bytes; -1 when missing.
    integer(i8) function meminfo_bytes(key)
        character(len=*), intent(in) :: key
            !! key with its colon

        integer :: unit, stat
        integer(i8) :: kb
        character(len=256) :: line, msg

        meminfo_bytes = -1
        open (newunit=unit, file="/proc/meminfo", action="read", status="old", iostat=stat, &
            iomsg=msg)
        if (stat /= 0) return
        do
            read (unit, "(a)", iostat=stat, iomsg=msg) line
            if (stat /= 0) exit
            if (line(1:len(key)) == key) then
                read (line(len(key) + 1:), *, iostat=stat, iomsg=msg) kb
                if (stat == 0) meminfo_bytes = 1024_i8*kb
                exit
            end if
        end do
        close (unit)
    end function meminfo_bytes

    !> The integer on the first line of a file; -1 when the file is missing or holds none.
    integer(i8) function first_number(path)
        character(len=*), intent(in) :: path
            !! file to read

        integer :: unit, stat
        integer(i8) :: value
        character(len=256) :: msg

        first_number = -1
        open (newunit=unit, file=path, action="read", status="old", iostat=stat, iomsg=msg)
        if (stat /= 0) return
        read (unit, *, iostat=stat, iomsg=msg) value
        if (stat == 0) first_number = value
        close (unit)
    end function first_number

end module mpm_system
