!> Verification: periodic faces (domain.boundaries "periodic": the nodes of the two faces of
!> an axis tied, mpm_grid::fold_periodic and slave_periodic).
!>
!> - A laterally infinite layer: a soil 2 m wide (8 cells of 0.25 m) and 4 m high between
!>   periodic x faces, its base shaken horizontally by a rigid seismic face (one sine pulse
!>   of 0.05 m/s over 0.1 s), linear shape functions, MUSL: every particle of a row moves as
!>   every other (the horizontal velocities of a row agree to 1e-12 of the largest), and the
!>   energy balance closes to 2 % of the work of the base (the grid's error at 18 cells per
!>   pulse length; 0.44 % on 2026-12-07). Without the tie the x faces are free and the rows
!>   bend (the check fails by orders of magnitude).
!> - A particle leaving through one face comes back through the other: a block filling the
!>   domain (4 x 2 cells, linear shape functions, no gravity) translating at 1 m/s along x for
!>   3 s crosses the periodic faces one and a half times: every particle is at its start
!>   position plus 3 m wrapped into the domain, within 1e-9 m, at 1 m/s still, none lost.
program test_periodic_face
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        energy_residual
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "periodic_face")
    call layer()
    call translation()
    call remove_file("test_periodic_face_pulse.csv")
    call finish(suite)

contains

    !> A shaken layer between periodic faces stays laterally uniform.
    subroutine layer()
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: spread, largest, y, residual, dt
        integer :: p, q

        call read_case_string('{"name": "layer", "domain": {"nx": 8, "ny": 16, "dx": 0.25, '// &
            '"boundaries": {"xmin": "periodic", "xmax": "periodic", "ymin": {"type": '// &
            '"seismic", "file": "'//pulse_file()//'", "record": "velocity", '// &
            '"scale": [1, 0]}}}, "particles": {"ppc": 2}, "materials": [{"name": "soil", '// &
            '"type": "linear_elastic", "E": 1e7, "nu": 0.3, "rho": 2000}], "bodies": '// &
            '[{"material": "soil", "min": [0, 0], "max": [2, 4]}], "gravity": [0, 0], '// &
            '"solver": {"scheme": "MUSL", "shape_function": "linear"}, '// &
            '"time": {"tend": 0.4, "cfl": 0.5}}', case, error, "layer")
        call check(suite, .not. allocated(error), "layer case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), "layer: simulation starts")
        if (allocated(error)) return
        do while (sim%time < case%time%tend - 1.0e-9_wp)
            dt = min(stable_time_step(sim), case%time%tend - sim%time)
            call advance(sim, dt, error)
            if (allocated(error)) then
                call check(suite, .false., "layer: run failed: "//error%message)
                return
            end if
        end do
        largest = maxval(abs(sim%particles%v(1, 1:sim%particles%n)))
        spread = 0.0_wp
        do p = 1, sim%particles%n
            y = sim%particles%x(2, p)
            do q = 1, sim%particles%n
                if (abs(sim%particles%x(2, q) - y) > 1.0e-3_wp) cycle
                spread = max(spread, abs(sim%particles%v(1, q) - sim%particles%v(1, p)))
            end do
        end do
        call check(suite, largest > 1.0e-3_wp, "layer: the pulse moved the soil")
        call check_close(suite, spread/largest, 0.0_wp, 1.0e-12_wp, "layer: every row moves " &
            //"as one (horizontal velocities of a row within 1e-12 of the largest)")
        residual = energy_residual(sim%energy)
        call check(suite, abs(residual) < 0.02_wp*abs(sim%energy%loads), "layer: energy " &
            //"residual below 2 % of the work of the base")
        print "(a,3(a,es10.3))", "layer", ": row spread / largest ", spread/largest, &
            ", residual / work ", residual/sim%energy%loads, ", work ", sim%energy%loads
    end subroutine layer

    !> A block translating through the periodic faces.
    subroutine translation()
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp), allocatable :: x0(:)
        real(wp) :: worst, expected, speed_error, dt
        integer :: p

        call read_case_string('{"name": "translation", "domain": {"nx": 4, "ny": 2, '// &
            '"dx": 0.5, "boundaries": {"xmin": "periodic", "xmax": "periodic"}}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "soil", "type": '// &
            '"linear_elastic", "E": 1e6, "nu": 0.3, "rho": 1000}], "bodies": [{"material": '// &
            '"soil", "min": [0, 0], "max": [2, 1], "velocity": [1, 0]}], "gravity": [0, 0], '// &
            '"solver": {"scheme": "MUSL", "shape_function": "linear"}, '// &
            '"time": {"tend": 3.0, "cfl": 0.5}}', case, error, "translation")
        call check(suite, .not. allocated(error), "translation case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), "translation: simulation starts")
        if (allocated(error)) return
        x0 = sim%particles%x(1, 1:sim%particles%n)
        do while (sim%time < case%time%tend - 1.0e-9_wp)
            dt = min(stable_time_step(sim), case%time%tend - sim%time)
            call advance(sim, dt, error)
            if (allocated(error)) then
                call check(suite, .false., "translation: run failed: "//error%message)
                return
            end if
        end do
        worst = 0.0_wp
        speed_error = 0.0_wp
        do p = 1, sim%particles%n
            expected = modulo(x0(p) + 3.0_wp, 2.0_wp)
            worst = max(worst, min(abs(sim%particles%x(1, p) - expected), &
                abs(abs(sim%particles%x(1, p) - expected) - 2.0_wp)))
            speed_error = max(speed_error, abs(sim%particles%v(1, p) - 1.0_wp) &
                + abs(sim%particles%v(2, p)))
        end do
        call check_close(suite, worst, 0.0_wp, 1.0e-9_wp, "translation: every particle at " &
            //"x0 + 3 m wrapped into the domain")
        call check_close(suite, speed_error, 0.0_wp, 1.0e-9_wp, "translation: at 1 m/s still")
        print "(a,2(a,es10.3))", "translation", ": worst position ", worst, ", worst speed ", &
            speed_error
    end subroutine translation

    !> Delete a file the test wrote (the working directory is CTest's).
    subroutine remove_file(path)
        character(len=*), intent(in) :: path
        integer :: unit, stat

        open (newunit=unit, file=path, status="old", iostat=stat)
        if (stat == 0) close (unit, status="delete")
    end subroutine remove_file

    !> A velocity record of one sine pulse, written for the test.
    function pulse_file() result(path)
        character(len=:), allocatable :: path
        integer :: unit, k
        real(wp) :: t

        path = "test_periodic_face_pulse.csv"
        open (newunit=unit, file=path, status="replace", action="write")
        write (unit, "(a)") "time,velocity"
        do k = 0, 200
            t = 0.001_wp*k
            if (t <= 0.1_wp) then
                write (unit, "(es24.16,',',es24.16)") t, 0.05_wp*sin(acos(-1.0_wp)*t/0.1_wp)**2
            else
                write (unit, "(es24.16,',',es24.16)") t, 0.0_wp
            end if
        end do
        close (unit)
    end function pulse_file

end program test_periodic_face
