!> Verification: regions of grid nodes moved at a prescribed velocity (`prescribed_motion`),
!> their reaction and the work they do.
!>
!> A plate pushes down the top of an elastic column (1 m wide, H = 2 m, sliding sides, fixed
!> base; E = 10 MPa, nu = 0.3) at 0.01 m/s ramped up over 0.2 s, holding only the vertical
!> velocity of the top row of nodes (a smooth plate). After 1 s the plate has moved
!> d = 0.01 (1 - 0.1) = 9 mm (its displacement, v F(t), exact), and the confined column
!> carries the stress M d / H, M = E (1 - nu) / ((1 + nu)(1 - 2 nu)): the plate's reaction is
!> -M d / H per metre of width, within 2 % (measured 0.55 %: the slow loading's inertia and
!> damping, and the top row of particles between the plate's nodes and the next); none
!> sideways. The energy balance books the plate's work as load work (residual below 0.5 % of
!> it). The same plate holding both components (a rough plate) has the same vertical
!> reaction, and a region that would move nodes of the fixed base sideways is refused with the
!> region, the node and the face named.
program test_prescribed_motion
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        energy_residual
    use mpm_motion, only: region_displacement
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "prescribed_motion")
    call plate("smooth plate", '"components": ["y"], ')
    call plate("rough plate", "")
    call refused()
    call finish(suite)

contains

    function column_case(region) result(text)
        character(len=*), intent(in) :: region
        character(len=:), allocatable :: text

        text = '{"name": "plate", "domain": {"nx": 10, "ny": 25, "dx": 0.1, "boundaries": ' &
            //'{"xmin": "sliding", "xmax": "sliding", "ymin": "fixed"}}, "particles": {"ppc": ' &
            //'2}, "materials": [{"name": "m", "type": "linear_elastic", "E": 1e7, "nu": 0.3, ' &
            //'"rho": 2000}], "bodies": [{"material": "m", "min": [0, 0], "max": [1, 2]}], ' &
            //'"prescribed_motion": ['//region//'], "solver": {"scheme": "MUSL", ' &
            //'"shape_function": "cpgimp"}, "time": {"tend": 1, "cfl": 0.5}, "damping": ' &
            //'{"type": "local", "value": 0.1}}'
    end function column_case

    subroutine plate(label, components)
        character(len=*), intent(in) :: label, components
        real(wp), parameter :: young = 1.0e7_wp, nu = 0.3_wp, height = 2.0_wp
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: modulus, d(3), expected, work

        call read_case_string(column_case('{"name": "plate", "min": [0, 1.95], "max": [1, ' &
            //'2.05], "velocity": [0, -0.01], '//components//'"time_function": {"type": ' &
            //'"ramp", "duration": 0.2}}'), case, error, label)
        if (.not. allocated(error)) call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), label//": set-up")
        if (allocated(error)) then
            print '(a)', error%message
            return
        end if
        do while (sim%time < case%time%tend)
            call advance(sim, min(stable_time_step(sim), case%time%tend - sim%time), error)
            if (allocated(error)) exit
        end do
        call check(suite, .not. allocated(error), label//": runs")
        if (allocated(error)) then
            print '(a)', error%message
            return
        end if
        d = region_displacement(case, 1, sim%time)
        call check(suite, abs(d(2) + 0.009_wp) < 1.0e-12_wp .and. d(1) == 0.0_wp, &
            label//": displacement v F(t) = 9 mm down")
        modulus = young*(1.0_wp - nu)/((1.0_wp + nu)*(1.0_wp - 2.0_wp*nu))
        expected = modulus*d(2)/height
        print '(a, 3es12.4)', "  "//label//": reaction x, y; expected y [N/m]", &
            sim%region_reaction(:, 1), expected
        call check(suite, abs(sim%region_reaction(2, 1)/expected - 1.0_wp) < 0.02_wp, &
            label//": reaction M d / H within 2 %")
        call check(suite, abs(sim%region_reaction(1, 1)) < 1.0e-6_wp*abs(expected), &
            label//": no sideways reaction")
        work = sim%energy%loads
        print '(a, 2es12.4)', "  "//label//": load work, energy residual [J/m]", work, &
            energy_residual(sim%energy)
        call check(suite, work > 0.0_wp .and. abs(energy_residual(sim%energy)) < 0.005_wp*work, &
            label//": the plate's work is booked (residual below 0.5 % of it)")
    end subroutine plate

    subroutine refused()
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        integer :: k

        call read_case_string(column_case('{"name": "lift", "min": [0.2, 0], "max": [0.6, ' &
            //'0.05], "velocity": [0.01, 0], "time_function": {"type": "ramp", "duration": ' &
            //'0.1}}'), case, error, "lift")
        if (.not. allocated(error)) call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), "base region: set-up")
        if (allocated(error)) return
        ! refused at its first step with a velocity (the ramp starts from rest)
        do k = 1, 100
            call advance(sim, stable_time_step(sim), error)
            if (allocated(error)) exit
        end do
        print "(a, i0)", "  lift: steps until refused: ", k
        call check(suite, allocated(error) .and. k == 2, "base region: refused at step 2")
        if (.not. allocated(error)) return
        call check(suite, error%code == 2 .and. index(error%message, &
            'prescribed_motion[1] "lift" moves the node at (0.3, 0) m along x, which ' &
            //"domain.boundaries holds there (face ymin)") > 0, "base region: message")
        print '(a)', "  "//error%message
    end subroutine refused

end program test_prescribed_motion
