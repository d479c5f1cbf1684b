!> The thread governor (mpm_threads) on step times made up for the test: it leaves a count
!> whose steps are slower (busy cores), keeps one that is faster (idle cores), finds the best
!> of several, costs little while it looks, does not wander on noise, and changes nothing
!> when asked not to (OMP_DYNAMIC=false, or one thread).
program test_mpm_threads
    use mpm_kinds, only: wp, i8
    use mpm_testing, only: test_suite_type, new_suite, check, check_contains, finish
    use mpm_threads, only: thread_governor_type, new_thread_governor, governor_threads, &
        governor_step, governor_text
    implicit none

    type(test_suite_type) :: suite
    type(thread_governor_type) :: gov
    real(wp) :: best, spent

    call new_suite(suite, "mpm_threads")

    ! busy cores: 2 threads take 10 times as long per step as 1 (ms steps, 60 s of wall time)
    call new_thread_governor(gov, most=2, adaptive=.true.)
    call simulate(gov, [1.0e-3_wp, 1.0e-2_wp], 60.0_wp, best, spent)
    call check(suite, governor_threads(gov) == 1, "busy cores: ends on 1 thread")
    call check(suite, gov%steps_with(1) > 50*gov%steps_with(2), &
        "busy cores: nearly every step on 1 thread")
    call check(suite, spent < 1.05_wp*best, &
        "busy cores: within 5 % of the time on 1 thread alone (trials included)")
    call check_contains(suite, governor_text(gov), "1:", "busy cores: the summary names 1 thread")

    ! idle cores: 2 threads twice as fast; the trials of 1 thread cost little
    call new_thread_governor(gov, most=2, adaptive=.true.)
    call simulate(gov, [2.0e-3_wp, 1.0e-3_wp], 60.0_wp, best, spent)
    call check(suite, governor_threads(gov) == 2, "idle cores: stays on 2 threads")
    call check(suite, gov%changes == 0, "idle cores: never changes")
    call check(suite, spent < 1.01_wp*best, &
        "idle cores: the trials cost less than 1 % of the run")
    call check(suite, gov%trials <= 8, "idle cores: the time between trials grows (8 at most in 60 s)")

    ! 8 threads allowed, 4 free cores: the best count is 4
    call new_thread_governor(gov, most=8, adaptive=.true.)
    call simulate(gov, [8.0e-3_wp, 4.0e-3_wp, 3.0e-3_wp, 2.0e-3_wp, 3.0e-3_wp, 5.0e-3_wp, &
        7.0e-3_wp, 9.0e-3_wp], 60.0_wp, best, spent)
    call check(suite, governor_threads(gov) == 4, "8 threads on 4 free cores: settles on 4")

    ! equal speeds with +-2 % noise: no change past the margin
    call new_thread_governor(gov, most=2, adaptive=.true.)
    call simulate(gov, [1.0e-3_wp, 1.0e-3_wp], 60.0_wp, best, spent, noise=0.02_wp)
    call check(suite, gov%changes <= 1, "noise of 2 %: at most one change")

    ! fixed (OMP_DYNAMIC=false) and one thread: never a trial
    call new_thread_governor(gov, most=2, adaptive=.false.)
    call simulate(gov, [1.0e-3_wp, 1.0e-2_wp], 10.0_wp, best, spent)
    call check(suite, governor_threads(gov) == 2 .and. gov%trials == 0 .and. &
        gov%steps_with(1) == 0, "fixed: every step on 2 threads")
    call check_contains(suite, governor_text(gov), "fixed", "fixed: the summary says so")
    call new_thread_governor(gov, most=1)
    call simulate(gov, [1.0e-3_wp], 10.0_wp, best, spent)
    call check(suite, .not. gov%adaptive .and. gov%trials == 0, "1 thread: nothing to choose")

    call finish(suite)

contains

    !> Run the governor for `wall` seconds of made-up steps: a step on n threads takes
    !> step(n) (times 1 + noise*u, u in [-1, 1] from a fixed sequence). `spent` is the time
    !> taken, `best` the time the same steps take on the fastest count throughout.
    subroutine simulate(gov, step, wall, best, spent, noise)
        type(thread_governor_type), intent(inout) :: gov
        real(wp), intent(in) :: step(:), wall
        real(wp), intent(out) :: best, spent
        real(wp), intent(in), optional :: noise

        real(wp) :: now, seconds, amplitude, u
        integer(i8) :: k

        amplitude = 0.0_wp
        if (present(noise)) amplitude = noise
        now = 0.0_wp
        best = 0.0_wp
        k = 0
        do while (now < wall)
            k = k + 1
            u = 2.0_wp*modulo(0.618033988749895_wp*real(k, wp), 1.0_wp) - 1.0_wp
            seconds = step(governor_threads(gov))*(1.0_wp + amplitude*u)
            best = best + minval(step)*(1.0_wp + amplitude*u)
            now = now + seconds
            call governor_step(gov, seconds, now)
        end do
        spent = now
    end subroutine simulate

end program test_mpm_threads
