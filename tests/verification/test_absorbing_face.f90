!> Verification: a viscous absorbing face (domain.boundaries.<face>.type = "absorbing").
!>
!> A laterally confined elastic column (sliding sides, 2D plane strain, 2 cells wide) 3 m
!> high, E = 1 MPa, nu = 0.3, rho = 1000 (P-wave speed vp = sqrt(M / rho) = 36.69 m/s), no
!> gravity, free top. At t = 0 a smooth P pulse travels down: between y = 1.6 and 2.4 m the
!> particles have v_y = -v0 sin^2(pi (y - 1.6) / 0.8), v0 = 0.05 m/s, and the stress of a
!> wave running towards -y, s_yy = rho vp v_y, s_xx = s_zz = nu / (1 - nu) s_yy. The pulse
!> reaches the base at 0.044 s and has left it by 0.066 s; the run lasts to 0.15 s.
!>
!> With the base absorbing (vp, vs of the column's material) the energy left in the column
!> (kinetic + elastic) is below 5 % of the pulse's (the target of the 1D wave test of issue
!> 22; a perfect boundary leaves none), the energy the dashpots took (booked with what the
!> faces stop, boundary_work) equals the energy that left within 5 %, and the energy residual
!> is below 2 % of the pulse's energy. The same column on a sliding (reflecting) base keeps more than 90 % of it: the
!> test tells an absorbing face from a reflecting one.
program test_absorbing_face
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        start_energy_balance, energy_residual
    implicit none

    real(wp), parameter :: young = 1.0e6_wp, nu = 0.3_wp, rho = 1000.0_wp, v0 = 0.05_wp
    real(wp), parameter :: pi = acos(-1.0_wp)
    type(test_suite_type) :: suite
    real(wp) :: modulus, vp, vs, left, taken, loads, residual, e0

    call new_suite(suite, "absorbing_face")
    modulus = young*(1 - nu)/((1 + nu)*(1 - 2*nu))
    vp = sqrt(modulus/rho)
    vs = sqrt(young/(2*(1 + nu))/rho)
    call run_pulse('{"type": "absorbing", "vp": '//fmt_real(vp)//', "vs": '// &
        fmt_real(vs)//'}', e0, left, taken, loads, residual)
    call check(suite, left < 0.05_wp*e0, "absorbing base: below 5 % of the pulse's energy left")
    call check_close(suite, taken, e0 - left, 0.05_wp*(e0 - left), &
        "absorbing base: the energy the dashpots took is what left, within 5 %")
    call check(suite, loads == 0.0_wp, "absorbing base: nothing booked as work of the loads")
    call check(suite, abs(residual) < 0.02_wp*e0, "absorbing base: residual below 2 %")
    print "(a,3(a,es10.3))", "absorbing base", ": energy left / pulse ", left/e0, &
        ", taken / energy that left - 1 ", taken/(e0 - left) - 1, ", residual / pulse ", &
        residual/e0
    call run_pulse('"sliding"', e0, left, taken, loads, residual)
    call check(suite, left > 0.9_wp*e0, "sliding base: the pulse reflects (above 90 % left)")
    call check(suite, abs(taken) < 1.0e-3_wp*e0, "sliding base: the faces take nothing")
    print "(a,2(a,es10.3))", "sliding base", ": energy left / pulse ", left/e0, &
        ", residual / pulse ", residual/e0
    call finish(suite)

contains

    !> The pulse in the column on the given base, to t = 0.15 s.
    subroutine run_pulse(base, e0, left, taken, loads, residual)
        character(len=*), intent(in) :: base
            !! the ymin face's JSON value
        real(wp), intent(out) :: e0
            !! kinetic + elastic energy of the pulse [J]
        real(wp), intent(out) :: left
            !! kinetic + elastic energy at the end [J]
        real(wp), intent(out) :: taken
            !! energy the faces took (boundary_work) [J]
        real(wp), intent(out) :: loads
            !! work of the loads [J]
        real(wp), intent(out) :: residual
            !! energy residual at the end [J]

        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: y, v, s
        integer :: p

        e0 = 1.0_wp
        left = 1.0_wp
        taken = 0.0_wp
        loads = 1.0_wp
        residual = 1.0_wp
        call read_case_string('{"name": "pulse", "domain": {"nx": 2, "ny": 60, "dx": 0.05, '// &
            '"boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": '//base//'}}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
            '"E": 1e6, "nu": 0.3, "rho": 1000}], "bodies": [{"material": "m", "min": [0, 0], '// &
            '"max": [0.1, 3.0]}], "gravity": [0, 0], '// &
            '"solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
            '"time": {"tend": 0.15, "cfl": 0.5}}', case, error, "pulse")
        call check(suite, .not. allocated(error), base//": case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        if (allocated(error)) return
        do p = 1, sim%particles%n
            y = sim%particles%x(2, p)
            v = 0.0_wp
            if (y > 1.6_wp .and. y < 2.4_wp) v = -v0*sin(pi*(y - 1.6_wp)/0.8_wp)**2
            s = rho*vp*v
            sim%particles%v(:, p) = [0.0_wp, v]
            sim%particles%stress(1:3, p) = [nu/(1 - nu)*s, s, nu/(1 - nu)*s]
        end do
        call start_energy_balance(sim)
        e0 = sim%energy%kinetic + sim%energy%elastic
        do while (sim%time < case%time%tend)
            call advance(sim, stable_time_step(sim), error)
            if (allocated(error)) then
                call check(suite, .false., base//": run failed: "//error%message)
                return
            end if
        end do
        left = sim%energy%kinetic + sim%energy%elastic
        taken = sim%energy%boundary
        loads = sim%energy%loads
        residual = energy_residual(sim%energy)
    end subroutine run_pulse

end program test_absorbing_face
