!> Verification: pore water of saturated soils (mpm_pore_water) against closed forms.
!>
!> - Skempton: an elastic skeleton (E = 10 MPa, nu = 0.25, K = 6.67 MPa) with pore water of
!>   K_w = 20 MPa and n = 0.4, undrained (k = 0), compressed slowly in an oedometer (a column
!>   of 1 x 4 cells, the top pushed down at 1 mm/s for 1 s): every particle's pore pressure
!>   is B times its mean total stress, B = 1 / (1 + n K / K_w) = 0.882 (Skempton's A = 1/3 of
!>   an elastic skeleton), within 0.5 %; the effective stress takes the rest, and the energy
!>   balance closes (the water's stored energy in the elastic term).
!> - Terzaghi: a column 1 m high of 10 cells (cpGIMP, MUSL), drained at the top, impermeable
!>   elsewhere, loaded at its top by 10 kPa ramped over one undrained wave transit (0.0204 s,
!>   which leaves no vibration of the column), c_v = 1 m2/s: the pore pressures of every
!>   particle against Terzaghi's series for that ramp at t = 0.05 .. 1 s (T_v = t), within
!>   2 % of the load (1.0 % on 2026-12-07; validation/terzaghi runs three resolutions);
!>   the energy balance closes to 0.1 % of the work of the load.
!> - Hydrostatic rest: a column 2 m high with the phreatic level at its top, gravity, K0
!>   stresses and a drained top stays at rest: the pore pressures remain rho_w g (h - y) and
!>   the vertical effective stress the buoyant weight above, within 1 %.
program test_pore_water
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        energy_residual
    implicit none

    real(wp), parameter :: pi = acos(-1.0_wp)
    type(test_suite_type) :: suite

    call new_suite(suite, "pore_water")
    call skempton()
    call terzaghi()
    call hydrostatic()
    call finish(suite)

contains

    !> Undrained oedometric compression: p = B sigma_mean.
    subroutine skempton()
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: b, worst, mean, residual
        integer :: p

        call read_case_string('{"name": "skempton", "domain": {"nx": 1, "ny": 4, "dx": 0.25, '// &
            '"boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": "sliding", '// &
            '"ymax": {"type": "velocity", "velocity": [0, -0.001]}}}, "particles": {"ppc": 2}, '// &
            '"materials": [{"name": "soil", "type": "linear_elastic", "E": 1e7, "nu": 0.25, '// &
            '"rho": 2000}], "bodies": [{"material": "soil", "min": [0, 0], "max": [0.25, 1]}], '// &
            '"pore_water": {"bulk_modulus": 2e7, "materials": [{"material": "soil", '// &
            '"porosity": 0.4, "permeability": 0}]}, "gravity": [0, 0], '// &
            '"solver": {"scheme": "MUSL"}, "time": {"tend": 1.0, "cfl": 0.5}}', case, error, &
            "skempton")
        call check(suite, .not. allocated(error), "Skempton case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call run(sim, case, error)
        if (allocated(error)) return
        b = 1.0_wp/(1.0_wp + 0.4_wp*(1.0e7_wp/(3.0_wp*(1.0_wp - 0.5_wp)))/2.0e7_wp)
        worst = 0.0_wp
        do p = 1, sim%particles%n
            mean = -sum(sim%particles%stress(1:3, p))/3.0_wp
            worst = max(worst, abs(sim%particles%pore_pressure(p)/mean - b))
        end do
        call check(suite, minval(sim%particles%pore_pressure(1:sim%particles%n)) > 1.0e3_wp, &
            "Skempton: the pore pressure rose (> 1 kPa)")
        call check_close(suite, worst, 0.0_wp, 0.005_wp*b, "Skempton: p / sigma_mean = B = " &
            //"1 / (1 + n K / K_w) at every particle, within 0.5 %")
        residual = energy_residual(sim%energy)
        call check(suite, abs(residual) < 0.01_wp*abs(sim%energy%loads), "Skempton: energy " &
            //"residual below 1 % of the work of the top face")
        print "(a,2(a,es10.3))", "skempton", ": worst |p/sigma_m - B| ", worst, &
            ", residual / work ", residual/sim%energy%loads
    end subroutine skempton

    !> 1D consolidation under a ramped top load against Terzaghi's series.
    subroutine terzaghi()
        real(wp), parameter :: m_oed = 1.0e7_wp, n = 0.3_wp, kw = 2.0e7_wp, load = 1.0e4_wp
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: p0, worst, next, dt, residual, depth
        integer :: p
        character(len=32) :: conductivity

        ! k = c_v gamma_w (1 / M + n / K_w)
        write (conductivity, "(es14.7)") 1000.0_wp*9.80665_wp*(1.0_wp/m_oed + n/kw)
        call read_case_string('{"name": "terzaghi", "domain": {"nx": 1, "ny": 10, "dx": 0.1, '// &
            '"boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": "sliding"}}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "soil", "type": "linear_elastic", '// &
            '"E": 1e7, "nu": 0, "rho": 2000}], "bodies": [{"material": "soil", '// &
            '"min": [0, 0], "max": [0.1, 1]}], "pore_water": {"bulk_modulus": 2e7, '// &
            '"materials": [{"material": "soil", "porosity": 0.3, "permeability": '// &
            trim(conductivity)//'}], "faces": {"ymax": "drained"}}, "loads": [{"name": "q", '// &
            '"type": "traction", "min": [0, 0.95], "max": [0.1, 1], "surface": "+y", '// &
            '"pressure": 1e4, "time_function": {"type": "ramp", "start": 0, "duration": 0.0204}}], '// &
            '"gravity": [0, 0], "solver": {"scheme": "MUSL"}, "time": {"tend": 1.0, "cfl": 0.5}}', &
            case, error, "terzaghi")
        call check(suite, .not. allocated(error), "Terzaghi case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), "Terzaghi: simulation starts")
        if (allocated(error)) return
        p0 = load*(1.0_wp/m_oed)/(1.0_wp/m_oed + n/kw)
        worst = 0.0_wp
        next = 0.05_wp
        do while (sim%time < case%time%tend - 1.0e-9_wp)
            dt = min(stable_time_step(sim), next - sim%time)
            call advance(sim, dt, error)
            if (allocated(error)) then
                call check(suite, .false., "Terzaghi: run failed: "//error%message)
                return
            end if
            if (sim%time >= next - 1.0e-12_wp) then
                do p = 1, sim%particles%n
                    depth = 1.0_wp - sim%particles%x(2, p)
                    worst = max(worst, abs(sim%particles%pore_pressure(p) &
                        - series(depth, sim%time, p0)))
                end do
                next = next + 0.05_wp
            end if
        end do
        call check_close(suite, worst/load, 0.0_wp, 0.02_wp, "Terzaghi: the pore pressures " &
            //"of every particle at t = 0.05 .. 1 s against the series, within 2 % of the load")
        residual = energy_residual(sim%energy)
        call check(suite, abs(residual) < 1.0e-3_wp*abs(sim%energy%loads), "Terzaghi: energy " &
            //"residual below 0.1 % of the work of the load")
        call check(suite, sim%energy%viscous > 0.3_wp*abs(sim%energy%loads), "Terzaghi: the " &
            //"flow dissipates (viscous term) a good part of the work of the load")
        print "(a,2(a,es10.3))", "terzaghi", ": worst |p - series| / q ", worst/load, &
            ", residual / work ", residual/sim%energy%loads

    end subroutine terzaghi

    !> A saturated column at rest under its weight, water table at the top.
    subroutine hydrostatic()
        real(wp), parameter :: rho = 2000.0_wp, rho_w = 1000.0_wp, g = 9.81_wp, top = 2.0_wp
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: worst_p, worst_s, depth
        integer :: p

        call read_case_string('{"name": "hydrostatic", "domain": {"nx": 1, "ny": 8, '// &
            '"dx": 0.25, "boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": "fixed"}}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "soil", "type": "linear_elastic", '// &
            '"E": 2e7, "nu": 0.3, "rho": 2000}], "bodies": [{"material": "soil", '// &
            '"min": [0, 0], "max": [0.25, 2]}], "pore_water": {"bulk_modulus": 1e8, '// &
            '"phreatic_level": 2.0, "materials": [{"material": "soil", "porosity": 0.4, '// &
            '"permeability": 1e-4}], "faces": {"ymax": "drained"}}, "gravity": [0, -9.81], '// &
            '"initial_stress": {"type": "k0"}, "solver": {"scheme": "MUSL"}, '// &
            '"time": {"tend": 0.2, "cfl": 0.5}}', case, error, "hydrostatic")
        call check(suite, .not. allocated(error), "hydrostatic case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call run(sim, case, error)
        if (allocated(error)) return
        worst_p = 0.0_wp
        worst_s = 0.0_wp
        do p = 1, sim%particles%n
            depth = top - sim%particles%x(2, p)
            worst_p = max(worst_p, abs(sim%particles%pore_pressure(p) - rho_w*g*depth))
            worst_s = max(worst_s, abs(sim%particles%stress(2, p) &
                + sim%particles%pore_pressure(p) + (rho - rho_w)*g*depth))
        end do
        call check_close(suite, worst_p/(rho_w*g*top), 0.0_wp, 0.01_wp, "hydrostatic: p = " &
            //"rho_w g (h - y) after 0.2 s, within 1 % of its largest")
        call check_close(suite, worst_s/((rho - rho_w)*g*top), 0.0_wp, 0.01_wp, "hydrostatic: " &
            //"sigma'_yy = - (rho - rho_w) g (h - y), within 1 % of its largest")
        print "(a,2(a,es10.3))", "hydrostatic", ": worst p ", worst_p/(rho_w*g*top), &
            ", worst sigma'_yy ", worst_s/((rho - rho_w)*g*top)
    end subroutine hydrostatic

    !> Run a case to its end at the stable time step.
    subroutine run(sim, case, error)
        type(simulation_type), intent(out) :: sim
        type(case_type), intent(in) :: case
        type(error_type), allocatable, intent(out) :: error
        real(wp) :: dt

        call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), case%name//": simulation starts")
        if (allocated(error)) return
        do while (sim%time < case%time%tend - 1.0e-9_wp)
            dt = min(stable_time_step(sim), case%time%tend - sim%time)
            call advance(sim, dt, error)
            if (allocated(error)) then
                call check(suite, .false., case%name//": run failed: "//error%message)
                return
            end if
        end do
    end subroutine run

    !> Terzaghi's series for a column of 1 m, c_v = 1 m2/s, a load ramped over 0.0204 s to
    !> the undrained pore pressure p0 [Pa].
    real(wp) function series(z, t, p0)
        real(wp), intent(in) :: z
            !! depth below the drained top [m]
        real(wp), intent(in) :: t
            !! time [s]
        real(wp), intent(in) :: p0
            !! undrained pore pressure of the full load [Pa]
        real(wp), parameter :: h = 1.0_wp, cv = 1.0_wp, ramp = 0.0204_wp
        real(wp) :: mm, tv, tr, f
        integer :: k

        tv = cv*t/h**2
        tr = cv*ramp/h**2
        series = 0.0_wp
        do k = 0, 400
            mm = pi*(2*k + 1)/2.0_wp
            if (tv <= tr) then
                f = (1.0_wp - exp(-mm**2*tv))/(mm**2*tr)
            else
                f = (exp(-mm**2*(tv - tr)) - exp(-mm**2*tv))/(mm**2*tr)
            end if
            series = series + 2.0_wp*p0/mm*sin(mm*z/h)*f
        end do
    end function series

end program test_pore_water
