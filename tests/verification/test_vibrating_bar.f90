!> Verification: axial vibration of an elastic bar (../shared/REFERENCES.md section 1).
!>
!> Bar of length L = 25 fixed at x = 0, free at x = L, E = 100, rho = 1, initial velocity
!> v0 sin(beta x), beta = pi / (2 L), run as a one-cell strip with sliding faces (nu = 0).
!> Exact centre-of-mass velocity: v_cm(t) = v0 / (beta L) cos(omega t), omega = beta sqrt(E/rho).
!> Checked with cpGIMP and each scheme (MUSL, USL, USF) over 3 periods: the period and the amplitude of v_cm within 1 %,
!> and the total energy (kinetic + strain) of this undamped run: no secular drift (the mean
!> over the last period equals the mean over the first within 0.1 %) and an oscillation
!> bounded by omega dt, the order of the phase lag between the kinetic energy (velocities of
!> the end of the step) and the stress work of explicit central differences.
program test_vibrating_bar
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        start_energy_balance, compute_energies, energy_residual
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "vibrating_bar")
    call run_bar("MUSL", "cpgimp")
    call run_bar("USL", "cpgimp")
    call run_bar("USF", "cpgimp")
    call run_bar("MUSL", "cpgimp", "apic")
    call run_bar("MUSL", "cpgimp", "pic")
    call finish(suite)

contains

    !> One run; `transfer` "apic" or "pic" (flip_fraction 0) instead of FLIP: their velocity
    !> update filters the particle velocities through the grid at every step, so the energy is
    !> expected to decay; checked against the same period and amplitude bands, APIC with a
    !> secular energy loss below 0.5 % over 3 periods, PIC (the contrast) above it.
    subroutine run_bar(scheme, shape, transfer)
        character(len=*), intent(in) :: scheme, shape
        character(len=*), intent(in), optional :: transfer

        real(wp), parameter :: length = 25.0_wp, young = 100.0_wp, rho = 1.0_wp, v0 = 0.1_wp
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: beta, omega, period, t_end, vcm, vcm_prev, t_prev, dt, amp_exact
        real(wp) :: crossings(16), vmax, vmin, e0, e, drift, measured_period
        real(wp) :: mean_first, mean_last, n_first, n_last, omega_dt, residual
        integer :: ncross, p
        character(len=:), allocatable :: label, extra

        label = scheme//"/"//shape
        extra = ""
        if (present(transfer)) then
            label = label//"/"//transfer
            if (transfer == "apic") extra = ', "transfer": "apic"'
            if (transfer == "pic") extra = ', "flip_fraction": 0'
        end if
        beta = acos(-1.0_wp)/(2*length)
        omega = beta*sqrt(young/rho)
        period = 2*acos(-1.0_wp)/omega
        t_end = 3.2_wp*period
        call read_case_string('{"name": "bar", "domain": {"nx": 52, "ny": 1, "dx": 0.5, '// &
            '"boundaries": {"xmin": "fixed", "ymin": "sliding", "ymax": "sliding"}}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
            '"E": 100, "nu": 0, "rho": 1}], "bodies": [{"material": "m", "min": [0, 0], '// &
            '"max": [25, 0.5]}], "solver": {"scheme": "'//scheme//'", "shape_function": "'// &
            shape//'"'//extra//'}, "time": {"tend": 40, "cfl": 0.4}}', case, error, "bar")
        call check(suite, .not. allocated(error), label//" case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        if (allocated(error)) return
        do p = 1, sim%particles%n
            sim%particles%v(:, p) = [v0*sin(beta*sim%particles%x(1, p)), 0.0_wp]
        end do
        call start_energy_balance(sim)
        e0 = sim%energy%kinetic
        amp_exact = v0/(beta*length)
        vcm_prev = centre_velocity(sim)
        t_prev = 0.0_wp
        ncross = 0
        vmax = -huge(1.0_wp)
        vmin = huge(1.0_wp)
        drift = 0.0_wp
        residual = 0.0_wp
        mean_first = 0.0_wp
        mean_last = 0.0_wp
        n_first = 0.0_wp
        n_last = 0.0_wp
        omega_dt = 0.0_wp
        do while (sim%time < t_end)
            dt = stable_time_step(sim)
            call advance(sim, dt, error)
            if (allocated(error)) then
                call check(suite, .false., label//" run: "//error%message)
                return
            end if
            vcm = centre_velocity(sim)
            vmax = max(vmax, vcm)
            vmin = min(vmin, vcm)
            if (vcm*vcm_prev < 0.0_wp .and. ncross < size(crossings)) then
                ncross = ncross + 1
                ! linear interpolation of the zero crossing
                crossings(ncross) = t_prev + (sim%time - t_prev)*vcm_prev/(vcm_prev - vcm)
            end if
            vcm_prev = vcm
            t_prev = sim%time
            call compute_energies(sim)
            e = sim%energy%kinetic + sim%energy%strain
            drift = max(drift, abs(e - e0)/e0)
            residual = max(residual, abs(energy_residual(sim%energy))/e0)
            omega_dt = max(omega_dt, omega*dt)
            if (sim%time <= period) then
                mean_first = mean_first + e
                n_first = n_first + 1
            else if (sim%time > t_end - period) then
                mean_last = mean_last + e
                n_last = n_last + 1
            end if
        end do
        mean_first = mean_first/n_first
        mean_last = mean_last/n_last
        call check(suite, ncross >= 6, label//" v_cm crosses zero at least 6 times")
        if (ncross < 6) return
        ! crossings k and k + 2 are one period apart; average over the available ones
        measured_period = (crossings(ncross) - crossings(ncross - 2*((ncross - 1)/2))) &
            /real((ncross - 1)/2, wp)
        call check_close(suite, measured_period, period, 0.01_wp*period, &
            label//" period of v_cm within 1 %")
        if (present(transfer)) then
            if (transfer == "pic") then
                call check(suite, mean_first - mean_last > 5.0e-3_wp*e0, &
                    label//" loses more than 0.5 % of the energy over 3 periods")
            else
                call check_close(suite, vmax, amp_exact, 0.01_wp*amp_exact, &
                    label//" positive amplitude of v_cm within 1 %")
                call check(suite, mean_last <= mean_first .and. &
                    mean_first - mean_last < 5.0e-3_wp*e0, &
                    label//" energy lost over 3 periods below 0.5 %")
            end if
        else
            call check_close(suite, vmax, amp_exact, 0.01_wp*amp_exact, &
                label//" positive amplitude of v_cm within 1 %")
            call check_close(suite, -vmin, amp_exact, 0.01_wp*amp_exact, &
                label//" negative amplitude of v_cm within 1 %")
            call check(suite, abs(mean_last - mean_first) < 1.0e-3_wp*e0, &
                label//" no secular energy drift over 3 periods (< 0.1 %)")
            call check(suite, drift < omega_dt, label//" energy oscillation below omega dt")
            ! the closed balance (kinetic + stored elastic energy, nothing dissipated): its
            ! residual is the same time-integration error
            call check(suite, residual < omega_dt, label//" energy residual below omega dt")
            call check(suite, abs(sim%energy%elastic - sim%energy%strain) < omega_dt*e0, &
                label//" stored elastic energy = work of the stresses within omega dt")
        end if
        print "(a,5(a,es10.3))", label, ": period error ", measured_period/period - 1, &
            ", amplitude error ", vmax/amp_exact - 1, ", energy oscillation ", drift, &
            " (bound ", omega_dt, "), secular drift ", (mean_last - mean_first)/e0
    end subroutine run_bar

    real(wp) function centre_velocity(sim)
        type(simulation_type), intent(in) :: sim
        centre_velocity = sum(sim%particles%mass*sim%particles%v(1, :))/sum(sim%particles%mass)
    end function centre_velocity

end program test_vibrating_bar
