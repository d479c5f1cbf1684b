!> How many OpenMP threads the steps of a run use: as many as make them fastest.
!>
!> On cores that other processes share (a laptop, a shared workstation, several images of a
!> hybrid run on one node), a thread that the system takes off its core holds up every other
!> thread at the end of each parallel loop: a run on 2 threads beside one busy process took
!> more than seven times as long as the same run on one thread. The results of a step do not
!> depend on the number of threads (the particles are sorted and chunked the same way, and
!> every sum is taken in a fixed order), so the count can change from one step to the next.
!>
!> The governor therefore measures. Now and then it runs a trial: a window of steps with the
!> present count, one with another count (half of it, or twice it, within 1 and the largest),
!> and one more with the present count; it keeps the other count when its steps were faster,
!> by more than `margin`, than the mean of the two windows around it. A trial that changes
!> nothing doubles the time to the next one (from `first_interval` up to `last_interval` of
!> wall time); one that changes the count brings it back to `first_interval`. The first
!> trial starts after the first step, so a run that starts on busy cores leaves them within
!> a fraction of a second.
!>
!> The largest count is the one OpenMP would use (OMP_NUM_THREADS, else the cores).
!> OMP_DYNAMIC=false keeps it for every step (benchmarks of a given thread count).
module mpm_threads
    !$ use omp_lib, only: omp_get_max_threads, omp_set_num_threads
    use mpm_kinds, only: wp, i8
    use mpm_strings, only: lower
    implicit none
    private
    public :: thread_governor_type, new_thread_governor, governor_threads, governor_step, &
        governor_text, set_threads

    real(wp), parameter :: first_interval = 1.0_wp
        !! wall time from a trial that changed the count to the next trial [s]
    real(wp), parameter :: last_interval = 32.0_wp
        !! longest wall time between two trials [s]
    real(wp), parameter :: margin = 0.05_wp
        !! how much faster the other count must be to be kept (fraction of the step time)
    integer, parameter :: window_steps = 5
        !! fewest steps of a window
    real(wp), parameter :: window_seconds = 0.1_wp
        !! a window ends once it has window_steps steps and this much wall time [s] ...
    real(wp), parameter :: longest_window = 0.5_wp
        !! ... or, whatever its steps, this much [s]

    !> The state of the governor of one run (one image).
    type :: thread_governor_type
        logical :: adaptive = .false.
            !! the count may change (more than one thread allowed, OMP_DYNAMIC not false)
        integer :: most = 1
            !! largest thread count
        integer :: current = 1
            !! thread count between trials
        integer :: other = 1
            !! the count a trial tries
        logical :: down = .true.
            !! the next trial from a count between 1 and most tries half of it
        integer :: window = 0
            !! 0: no trial; 1, 2, 3: the window of the trial under way (2: `other`)
        integer :: window_count = 0
            !! steps of the window so far
        real(wp) :: window_time = 0.0_wp
            !! step time of the window so far [s]
        real(wp) :: mean(3) = 0.0_wp
            !! mean step time of each window of the trial [s]
        real(wp) :: interval = first_interval
            !! wall time from the end of a trial to the next [s]
        real(wp) :: next_trial = 0.0_wp
            !! the clock (`now` of governor_step) at which the next trial starts [s]
        integer :: trials = 0
            !! trials done
        integer :: changes = 0
            !! trials that changed the count
        integer(i8), allocatable :: steps_with(:)
            !! steps run with each thread count (1:most)
    end type thread_governor_type

contains

    !> A governor for a run with up to `most` threads (default: what OpenMP would use);
    !> `adaptive` forces the choice (default: adaptive unless OMP_DYNAMIC is false).
    subroutine new_thread_governor(gov, most, adaptive)
        type(thread_governor_type), intent(out) :: gov
            !! the governor
        integer, intent(in), optional :: most
            !! largest thread count
        logical, intent(in), optional :: adaptive
            !! whether the count may change

        character(len=16) :: value
        integer :: length, stat

        gov%most = 1
        !$ gov%most = omp_get_max_threads()
        if (present(most)) gov%most = max(1, most)
        gov%adaptive = .true.
        call get_environment_variable("OMP_DYNAMIC", value, length, stat)
        ! (OpenMP's values are true and false, in any letter case)
        if (stat == 0 .and. length > 0) gov%adaptive = lower(trim(adjustl(value))) /= "false"
        if (present(adaptive)) gov%adaptive = adaptive
        gov%adaptive = gov%adaptive .and. gov%most > 1
        gov%current = gov%most
        gov%other = gov%most
        allocate (gov%steps_with(gov%most), source=0_i8)
    end subroutine new_thread_governor

    !> The thread count for the next step.
    pure integer function governor_threads(gov)
        type(thread_governor_type), intent(in) :: gov
            !! the governor
        governor_threads = gov%current
        if (gov%window == 2) governor_threads = gov%other
    end function governor_threads

    !> Record a step of `seconds` run with governor_threads(gov) threads, at clock `now`, and
    !> move the trial on.
    subroutine governor_step(gov, seconds, now)
        type(thread_governor_type), intent(inout) :: gov
            !! the governor
        real(wp), intent(in) :: seconds
            !! wall time of the step (the solver's step only, not the outputs) [s]
        real(wp), intent(in) :: now
            !! a clock that only goes forward [s]

        integer :: used
        real(wp) :: around

        used = governor_threads(gov)
        gov%steps_with(used) = gov%steps_with(used) + 1
        if (.not. gov%adaptive) return
        if (gov%window == 0) then
            if (now >= gov%next_trial) call start_trial(gov)
            return
        end if
        gov%window_count = gov%window_count + 1
        gov%window_time = gov%window_time + seconds
        if ((gov%window_count < window_steps .or. gov%window_time < window_seconds) .and. &
            gov%window_time < longest_window) return
        gov%mean(gov%window) = gov%window_time/gov%window_count
        gov%window_count = 0
        gov%window_time = 0.0_wp
        gov%window = gov%window + 1
        if (gov%window <= 3) return
        ! the trial is over
        gov%window = 0
        gov%trials = gov%trials + 1
        around = 0.5_wp*(gov%mean(1) + gov%mean(3))
        if (gov%mean(2) < (1.0_wp - margin)*around) then
            gov%current = gov%other
            gov%changes = gov%changes + 1
            gov%interval = first_interval
        else
            gov%interval = min(2.0_wp*gov%interval, last_interval)
            gov%down = .not. gov%down
        end if
        gov%next_trial = now + gov%interval
    end subroutine governor_step

    !> Begin a trial from the present count towards fewer or more threads.
    subroutine start_trial(gov)
        type(thread_governor_type), intent(inout) :: gov

        if (gov%current == gov%most) then
            gov%down = .true.
        else if (gov%current == 1) then
            gov%down = .false.
        end if
        if (gov%down) then
            gov%other = max(1, gov%current/2)
        else
            gov%other = min(gov%most, 2*gov%current)
        end if
        gov%window = 1
        gov%window_count = 0
        gov%window_time = 0.0_wp
    end subroutine start_trial

    !> Use n threads in the parallel loops that follow (no-op without OpenMP).
    subroutine set_threads(n)
        integer, intent(in) :: n
            !! thread count
        !$ call omp_set_num_threads(max(1, n))
    end subroutine set_threads

    !> One line for the run summary: the count and, when it changed, the steps of each.
    function governor_text(gov) result(text)
        type(thread_governor_type), intent(in) :: gov
            !! the governor
        character(len=:), allocatable :: text

        integer(i8) :: total
        integer :: n
        character(len=32) :: buf

        write (buf, "(i0)") gov%most
        text = trim(buf)
        if (.not. gov%adaptive) then
            if (gov%most > 1) text = text//" (fixed: OMP_DYNAMIC=false)"
            return
        end if
        total = sum(gov%steps_with)
        if (total == 0 .or. gov%steps_with(gov%most) == total) then
            text = text//" (adaptive; every step on "//trim(buf)//")"
            return
        end if
        text = text//" at most (adaptive; steps on"
        do n = 1, gov%most
            if (gov%steps_with(n) == 0) cycle
            write (buf, "(1x,i0,a,f5.1,a)") n, ":", &
                100.0_wp*real(gov%steps_with(n), wp)/real(total, wp), " %,"
            text = text//trim(buf)
        end do
        text = text(1:len(text) - 1)//")"
    end function governor_text

end module mpm_threads
