!> Stability stress tests of the explicit scheme.
!>
!> - Undamped elastic vibrating bar (REFERENCES.md section 1, cpGIMP) up to the stability
!>   limit: MUSL at CFL 0.5 and 1.0 (dt = dx / c, the limit of central differences), USL at
!>   0.5 (USL takes the velocity gradient from v_i = p_i / m_i of lightly loaded nodes; on
!>   this bar it loses its energy balance within 20 periods at CFL 0.8 and throws the free end
!>   off at 1.0): over 20 periods the energy (kinetic + strain) has no secular drift above 1 %
!>   and the run stays bounded.
!> - The same bar forced to CFL 3 (time.allow_unstable): the blow-up guard stops it with
!>   exit code 3 and a message naming the step, the particle and the quantity, before any NaN
!>   reaches the state.
program test_stability
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_contains, finish
    use mpm_error, only: error_type, exit_numerical
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        start_energy_balance
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "stability")
    call stable_run("MUSL", "0.5")
    call stable_run("MUSL", "1.0")
    call stable_run("USL", "0.5")
    call unstable_run("MUSL", "3.0")
    call unstable_run("USL", "3.0")
    call finish(suite)

contains

    subroutine bar(scheme, cfl, unstable, sim, error)
        character(len=*), intent(in) :: scheme, cfl
        logical, intent(in) :: unstable
        type(simulation_type), intent(out) :: sim
        type(error_type), allocatable, intent(out) :: error

        type(case_type) :: case
        character(len=:), allocatable :: extra
        real(wp) :: beta
        integer :: p

        extra = ""
        if (unstable) extra = ', "allow_unstable": true'
        call read_case_string('{"name": "bar", "domain": {"nx": 52, "ny": 1, "dx": 0.5, '// &
            '"boundaries": {"xmin": "fixed", "ymin": "sliding", "ymax": "sliding"}}, '// &
            '"materials": [{"name": "m", "type": "linear_elastic", "E": 100, "nu": 0, '// &
            '"rho": 1}], "bodies": [{"material": "m", "min": [0, 0], "max": [25, 0.5]}], '// &
            '"solver": {"scheme": "'//scheme//'", "shape_function": "cpgimp"}, '// &
            '"time": {"tend": 200, "cfl": '//cfl//extra//'}}', case, error, "bar")
        if (allocated(error)) return
        call new_simulation(sim, case, error)
        if (allocated(error)) return
        beta = acos(-1.0_wp)/50.0_wp
        do p = 1, sim%particles%n
            sim%particles%v(:, p) = [0.1_wp*sin(beta*sim%particles%x(1, p)), 0.0_wp]
        end do
        call start_energy_balance(sim)
    end subroutine bar

    !> 20 periods (T = 10 s) at a CFL factor up to the limit: bounded, no secular drift.
    subroutine stable_run(scheme, cfl)
        character(len=*), intent(in) :: scheme, cfl

        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: e0, e, mean_first, mean_last, n_first, n_last
        character(len=:), allocatable :: label

        label = scheme//" CFL "//cfl
        call bar(scheme, cfl, .false., sim, error)
        call check(suite, .not. allocated(error), label//": set-up")
        if (allocated(error)) return
        e0 = sim%energy%kinetic
        mean_first = 0.0_wp
        mean_last = 0.0_wp
        n_first = 0.0_wp
        n_last = 0.0_wp
        do while (sim%time < 200.0_wp)
            call advance(sim, stable_time_step(sim), error)
            if (allocated(error)) exit
            e = sim%energy%kinetic + sim%energy%strain
            if (sim%time <= 10.0_wp) then
                mean_first = mean_first + e
                n_first = n_first + 1
            else if (sim%time > 190.0_wp) then
                mean_last = mean_last + e
                n_last = n_last + 1
            end if
        end do
        call check(suite, .not. allocated(error), label//": 20 periods run without failure")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        mean_first = mean_first/n_first
        mean_last = mean_last/n_last
        call check(suite, abs(mean_last - mean_first) < 0.01_wp*e0, &
            label//": energy drift over 20 periods below 1 %")
        print "(a,a,es10.3)", label, ": energy drift over 20 periods ", (mean_last - mean_first)/e0
    end subroutine stable_run

    !> Forced past the stability limit: stopped by the guard with exit code 3.
    subroutine unstable_run(scheme, cfl)
        character(len=*), intent(in) :: scheme, cfl

        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        character(len=:), allocatable :: label
        integer :: steps

        label = scheme//" CFL "//cfl
        call bar(scheme, cfl, .true., sim, error)
        call check(suite, .not. allocated(error), label//": allow_unstable accepts the case")
        if (allocated(error)) return
        steps = 0
        do while (sim%time < 200.0_wp .and. steps < 20000)
            call advance(sim, stable_time_step(sim), error)
            steps = steps + 1
            if (allocated(error)) exit
        end do
        call check(suite, allocated(error), label//": the blow-up is detected")
        if (.not. allocated(error)) return
        call check(suite, error%code == exit_numerical, label//": exit code 3")
        call check_contains(suite, error%message, "step ", label//": message names the step")
        call check_contains(suite, error%message, "particle ", label// &
            ": message names the particle")
        call check_contains(suite, error%message, "unstable", label// &
            ": message says the run became unstable")
        call check(suite, index(error%message, "created energy") > 0 .or. &
            index(error%message, "moved") > 0 .or. index(error%message, "not finite") > 0, &
            label//": message names the quantity")
        call check(suite, all(abs(sim%particles%v) <= huge(1.0_wp)) .and. &
            all(abs(sim%particles%stress) <= huge(1.0_wp)), &
            label//": stopped before NaN or Inf reached the particles")
        print "(a,a)", label, ": "//error%message
    end subroutine unstable_run

end program test_stability
