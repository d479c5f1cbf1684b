!> The memory bandwidth of this machine, as STREAM's triad measures it (McCalpin, "Memory
!> bandwidth and machine balance in current high performance computers", 1995):
!> a(i) = b(i) + s c(i) over three arrays far larger than the caches, with the threads
!> OpenMP gives (OMP_NUM_THREADS), each thread on the part of the arrays it first touched.
!> Prints the best of the repetitions in GB/s counted as STREAM counts (24 bytes per element:
!> two reads and one write) and with the write-allocate read a store to a line not in cache
!> costs (32 bytes per element), and one machine-readable line ("TRIAD key=value ...").
!> bench/run_bench.sh runs it beside the cases so that docs/performance.md can state the
!> fraction of this bandwidth each case reaches.
!> Usage: stream_triad [megabytes per array]   (default 256)
program stream_triad
    use, intrinsic :: iso_fortran_env, only: int64, real64, output_unit
    use omp_lib, only: omp_get_max_threads, omp_get_wtime
    implicit none

    integer, parameter :: repetitions = 12
    real(real64), allocatable :: a(:), b(:), c(:)
    real(real64) :: s, best, t0, t, check
    integer(int64) :: n, i
    integer :: r, megabytes, status
    character(len=32) :: arg

    megabytes = 256
    if (command_argument_count() >= 1) then
        call get_command_argument(1, arg)
        read (arg, *, iostat=status) megabytes
        if (status /= 0 .or. megabytes < 1) then
            write (*, '(a)') "stream_triad: the argument is megabytes per array, a positive "// &
                "integer (got '"//trim(arg)//"')"
            error stop 2
        end if
    end if
    n = int(megabytes, int64)*1024_int64*1024_int64/8_int64
    allocate (a(n), b(n), c(n))
    ! first touch by the threads that later work on each part (the pages on their node)
    !$omp parallel do schedule(static)
    do i = 1, n
        a(i) = 0.0_real64
        b(i) = 1.0_real64
        c(i) = 2.0_real64
    end do
    !$omp end parallel do
    s = 3.0_real64
    best = huge(1.0_real64)
    do r = 1, repetitions
        t0 = omp_get_wtime()
        !$omp parallel do schedule(static)
        do i = 1, n
            a(i) = b(i) + s*c(i)
        end do
        !$omp end parallel do
        t = omp_get_wtime() - t0
        best = min(best, t)
        ! keep the loop from being seen as dead, and feed the next repetition
        b(1 + mod(r, int(n))) = a(1 + mod(r*7, int(n)))*1.0e-300_real64
    end do
    check = a(n/2)
    write (output_unit, '(a, i0, a, i0, a, f8.2, a, f8.2, a)') "triad: ", omp_get_max_threads(), &
        " threads, ", megabytes, " MB per array: ", 24.0_real64*real(n, real64)/best/1.0e9_real64, &
        " GB/s (24 B per element), ", 32.0_real64*real(n, real64)/best/1.0e9_real64, &
        " GB/s with the write-allocate read"
    write (output_unit, '(a, i0, a, i0, a, f0.3, a, f0.3, a, es10.3)') "TRIAD threads=", &
        omp_get_max_threads(), " mb_per_array=", megabytes, " gb_per_s=", &
        24.0_real64*real(n, real64)/best/1.0e9_real64, " gb_per_s_write_allocate=", &
        32.0_real64*real(n, real64)/best/1.0e9_real64, " check=", check
end program stream_triad
