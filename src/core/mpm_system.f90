!> Facts about the running process (Linux /proc), for summaries and benchmarks.
module mpm_system
    use mpm_kinds, only: wp
    implicit none
    private
    public :: peak_memory_mb

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

end module mpm_system
