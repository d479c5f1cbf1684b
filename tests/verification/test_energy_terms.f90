!> Verification: the dissipation terms of the energy balance, each against a closed form.
!>
!> 1. Local damping, a damped oscillator. The elastic bar of test_vibrating_bar (L = 25, fixed
!>    at x = 0, free at x = L, E = 100, rho = 1, nu = 0, a one-cell strip between sliding faces)
!>    starts in its first mode, v = v0 sin(beta x), with local damping alpha. Every node then
!>    moves in phase, with the nodal force -k_i u_i of the mode, and local damping adds
!>    -alpha |f| sign(v): the stiffness is k (1 + alpha) while the node moves away from rest and
!>    k (1 - alpha) while it returns, so each half period keeps (1 - alpha) / (1 + alpha) of the
!>    energy (exact for an oscillator of one degree of freedom). Checked: the damping work
!>    against the energy lost, kinetic + elastic at the start minus now, within omega dt of the
!>    initial energy (the phase lag of explicit central differences between the kinetic energy
!>    and the stress work, the energy error of the undamped bar in test_vibrating_bar); the peaks
!>    of the kinetic energy of the first three periods against KE_0 ((1 - alpha) / (1 + alpha))^n
!>    within omega dt / 2 (at a peak the elastic energy is near zero, so the phase lag enters
!>    at second order; what remains is the higher modes that the nonlinear damping excites, of
!>    order alpha^2). The test would see the damping missing: 45 % of the energy is lost.
!> 2. Viscous dissipation, a viscously damped oscillator. A Newtonian fluid (bulk modulus K,
!>    viscosity mu) in a one-cell strip between sliding faces, fixed at x = 0 and x = L, starts
!>    in the mode v = V sin(k x), k = pi / L. In plane strain the axial viscous stress of the mode
!>    is (4/3) mu du/dx, so its amplitude U obeys U'' + 2 zeta omega U' + omega^2 U = 0 with
!>    omega = k sqrt(K / rho), 2 zeta omega = (4/3) (mu / rho) k^2. The energy of the mode is
!>    (rho / 2)(U'^2 + omega^2 U^2) per unit of the mode's mass (times L / 2 per unit area).
!>    Checked: the viscous work (the work of the stresses beyond the stored compression
!>    energy) against the energy the exact solution has lost, at every step of 3 periods,
!>    within omega dt of the initial energy (the same time-integration error as above), and the
!>    residual within omega dt; no plastic, damping or friction work.
program test_energy_terms
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        start_energy_balance, compute_energies, energy_residual
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "energy_terms")
    call damped_bar("MUSL", 0.05_wp, "0.05")
    call damped_bar("USL", 0.05_wp, "0.05")
    call damped_bar("MUSL", 0.15_wp, "0.15")
    call viscous_mode("MUSL")
    call viscous_mode("USL")
    call finish(suite)

contains

    !> The bar of test_vibrating_bar with local damping alpha.
    subroutine damped_bar(scheme, alpha, alpha_text)
        character(len=*), intent(in) :: scheme
        real(wp), intent(in) :: alpha
        character(len=*), intent(in) :: alpha_text

        real(wp), parameter :: length = 25.0_wp, young = 100.0_wp, rho = 1.0_wp, v0 = 0.1_wp
        integer, parameter :: npeaks = 6
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: beta, omega, period, t_end, dt, e0, ke0, ratio, omega_dt, band
        real(wp) :: ke(3), peaks(npeaks), worst_peak, lost, worst_work
        integer :: p, npeak, n
        character(len=:), allocatable :: label

        label = scheme//", local damping "//alpha_text
        beta = acos(-1.0_wp)/(2*length)
        omega = beta*sqrt(young/rho)
        period = 2*acos(-1.0_wp)/omega
        t_end = 3.1_wp*period
        call read_case_string('{"name": "bar", "domain": {"nx": 52, "ny": 1, "dx": 0.5, '// &
            '"boundaries": {"xmin": "fixed", "ymin": "sliding", "ymax": "sliding"}}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
            '"E": 100, "nu": 0, "rho": 1}], "bodies": [{"material": "m", "min": [0, 0], '// &
            '"max": [25, 0.5]}], "solver": {"scheme": "'//scheme//'", "shape_function": '// &
            '"cpgimp"}, "damping": {"type": "local", "value": '//alpha_text//'}, '// &
            '"time": {"tend": 40, "cfl": 0.4}}', case, error, "bar")
        call check(suite, .not. allocated(error), label//": case is valid")
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
        e0 = sim%energy%initial
        ke0 = sim%energy%kinetic
        ratio = (1.0_wp - alpha)/(1.0_wp + alpha)
        ! kinetic energy of the last three steps, to find its peaks
        ke = ke0
        npeak = 0
        omega_dt = 0.0_wp
        worst_work = 0.0_wp
        do while (sim%time < t_end)
            dt = stable_time_step(sim)
            omega_dt = max(omega_dt, omega*dt)
            call advance(sim, dt, error)
            if (allocated(error)) then
                call check(suite, .false., label//": run failed: "//error%message)
                return
            end if
            call compute_energies(sim)
            ke = [ke(2:3), sim%energy%kinetic]
            ! a peak of the kinetic energy (the bar passes its rest shape), not the start
            if (ke(2) > ke(1) .and. ke(2) >= ke(3) .and. sim%time > 0.25_wp*period .and. &
                npeak < npeaks) then
                npeak = npeak + 1
                peaks(npeak) = ke(2)
            end if
            lost = e0 - sim%energy%kinetic - sim%energy%elastic
            worst_work = max(worst_work, abs(sim%energy%damping - lost)/e0)
        end do
        call check(suite, npeak == npeaks, label//": six peaks of the kinetic energy in 3 periods")
        if (npeak < npeaks) return
        band = 0.5_wp*omega_dt
        worst_peak = 0.0_wp
        do n = 1, npeaks
            worst_peak = max(worst_peak, abs(peaks(n)/ke0 - ratio**n)/ratio**n)
        end do
        call check(suite, worst_peak < band, label//": kinetic energy peak n = KE_0 ((1 - "// &
            "alpha)/(1 + alpha))^n within omega dt / 2")
        call check(suite, worst_work < omega_dt, label//": damping work = energy lost within "// &
            "omega dt of the initial energy")
        call check(suite, sim%energy%damping > 0.3_wp*e0, label//": damping removes more "// &
            "than 30 % of the energy in 3 periods (the test sees it)")
        call check(suite, abs(energy_residual(sim%energy)) < omega_dt*e0, &
            label//": residual below omega dt")
        call check(suite, sim%energy%plastic == 0.0_wp .and. sim%energy%viscous == 0.0_wp &
            .and. sim%energy%friction == 0.0_wp, label//": no plastic, viscous or friction work")
        print "(a,4(a,es10.3))", label, ": worst peak error ", worst_peak, &
            ", damping work error ", worst_work, ", residual ", &
            energy_residual(sim%energy)/e0, " (bound omega dt ", omega_dt
    end subroutine damped_bar

    !> The first axial mode of a Newtonian fluid strip between two fixed faces.
    subroutine viscous_mode(scheme)
        character(len=*), intent(in) :: scheme

        real(wp), parameter :: length = 1.0_wp, rho = 1000.0_wp, bulk = 1.0e6_wp
        real(wp), parameter :: mu = 755.0_wp, v_amp = 0.01_wp
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: k, omega, zeta, omega_d, period, t_end, dt, omega_dt, e0, t, decay
        real(wp) :: u, du, exact_lost, worst
        integer :: p
        character(len=:), allocatable :: label

        label = scheme//", Newtonian fluid mode"
        k = acos(-1.0_wp)/length
        omega = k*sqrt(bulk/rho)
        zeta = (4.0_wp/3.0_wp)*(mu/rho)*k**2/(2*omega)
        omega_d = omega*sqrt(1.0_wp - zeta**2)
        period = 2*acos(-1.0_wp)/omega_d
        t_end = 3.0_wp*period
        call read_case_string('{"name": "fluid", "domain": {"nx": 20, "ny": 1, "dx": 0.05, '// &
            '"boundaries": {"xmin": "fixed", "xmax": "fixed", "ymin": "sliding", '// &
            '"ymax": "sliding"}}, "particles": {"ppc": 2}, "materials": [{"name": "w", '// &
            '"type": "newtonian", "viscosity": 755, "bulk_modulus": 1e6, "rho": 1000}], '// &
            '"bodies": [{"material": "w", "min": [0, 0], "max": [1, 0.05]}], '// &
            '"solver": {"scheme": "'//scheme//'", "shape_function": "cpgimp"}, '// &
            '"time": {"tend": 1, "cfl": 0.4}}', case, error, "fluid")
        call check(suite, .not. allocated(error), label//": case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        if (allocated(error)) return
        do p = 1, sim%particles%n
            sim%particles%v(:, p) = [v_amp*sin(k*sim%particles%x(1, p)), 0.0_wp]
        end do
        call start_energy_balance(sim)
        e0 = sim%energy%initial
        omega_dt = 0.0_wp
        worst = 0.0_wp
        do while (sim%time < t_end)
            dt = stable_time_step(sim)
            omega_dt = max(omega_dt, omega*dt)
            call advance(sim, dt, error)
            if (allocated(error)) then
                call check(suite, .false., label//": run failed: "//error%message)
                return
            end if
            call compute_energies(sim)
            ! exact U(t) = (V / omega_d) exp(-zeta omega t) sin(omega_d t); energy ratio
            ! (U'^2 + omega^2 U^2) / V^2
            t = sim%time
            decay = exp(-zeta*omega*t)
            u = decay*sin(omega_d*t)/omega_d
            du = decay*(cos(omega_d*t) - zeta*omega*sin(omega_d*t)/omega_d)
            exact_lost = e0*(1.0_wp - du**2 - omega**2*u**2)
            worst = max(worst, abs(sim%energy%viscous - exact_lost)/e0)
        end do
        call check(suite, exact_lost > 0.5_wp*e0, label//": the mode loses more than half "// &
            "its energy in 3 periods (the test sees the dissipation)")
        call check(suite, worst < omega_dt, label//": viscous work = energy lost by the "// &
            "exact damped mode within omega dt")
        call check(suite, abs(energy_residual(sim%energy)) < omega_dt*e0, &
            label//": residual below omega dt")
        call check(suite, sim%energy%plastic == 0.0_wp .and. sim%energy%damping == 0.0_wp &
            .and. sim%energy%friction == 0.0_wp, label//": no plastic, damping or friction work")
        print "(a,5(a,es10.3))", label, ": zeta ", zeta, ", exact loss ", exact_lost/e0, &
            ", viscous work error ", worst, ", residual ", energy_residual(sim%energy)/e0, &
            " (omega dt ", omega_dt
    end subroutine viscous_mode

end program test_energy_terms
