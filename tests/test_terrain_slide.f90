!> Verification of the STL terrain contact (contact.type = "terrain_stl"): a block sliding on
!> an STL floor under a tilted gravity vector (../shared/REFERENCES.md section 4).
!>
!> The floor is the plane y = 0.11 m of tests/data/stl/floor_*.stl, between two grid lines
!> (dx = 0.02 m), so the contact is found from the distances to the surface, not from a face
!> of the grid. Gravity g (sin theta, -cos theta), theta = 30 deg, Coulomb friction mu. Exact:
!> s(t) = g (sin theta - mu cos theta) t^2 / 2 while mu < tan theta; the block sticks for
!> mu >= tan theta. Checked: the mean displacement along the floor within 2 % for mu = 0,
!> 0.2, 0.4, below 0.2 % of the frictionless slide for mu = 0.6, no lift-off, no particle
!> below the floor, and the same slide (to 1e-9) with the floor as 2 or as 2 000 triangles.
program test_terrain_slide
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: g = 9.81_wp, tend = 0.5_wp, floor_y = 0.11_wp
    real(wp) :: theta, s_free, s2, s2000

    call new_suite(suite, "terrain_slide")
    theta = acos(-1.0_wp)/6
    s_free = 0.5_wp*g*sin(theta)*tend**2
    call run_block(0.0_wp, "0.0", "floor_2", s2)
    call run_block(0.2_wp, "0.2", "floor_2", s2)
    call run_block(0.4_wp, "0.4", "floor_2", s2)
    call run_block(0.6_wp, "0.6", "floor_2", s2)
    ! the triangulation does not matter
    call run_block(0.4_wp, "0.4", "floor_2000", s2000)
    call run_block(0.4_wp, "0.4", "floor_2", s2)
    call check_close(suite, s2000, s2, 1.0e-9_wp*abs(s2), &
        "the same slide on 2 and on 2 000 triangles")
    call finish(suite)

contains

    subroutine run_block(mu, mu_text, floor, s)
        real(wp), intent(in) :: mu
        character(len=*), intent(in) :: mu_text, floor
        real(wp), intent(out) :: s

        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        character(len=64) :: gravity
        character(len=:), allocatable :: label
        real(wp) :: s_exact, lift, lowest

        s = 0.0_wp
        label = "mu = "//mu_text//", "//floor
        write (gravity, "(a,es23.16,a,es23.16,a)") "[", g*sin(theta), ", ", -g*cos(theta), "]"
        call read_case_string('{"name": "block", "domain": {"nx": 60, "ny": 10, "dx": 0.02}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
            '"E": 1e8, "nu": 0.3, "rho": 2000}], "bodies": [{"material": "m", '// &
            '"min": [0.1, 0.11], "max": [0.3, 0.15]}], "gravity": '//trim(gravity)//', '// &
            '"contact": {"type": "terrain_stl", "mu": '//mu_text//', "file": '// &
            '"tests/data/stl/'//floor//'.stl"}, '// &
            '"solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
            '"time": {"tend": 0.5, "cfl": 0.5}}', case, error, "block")
        call check(suite, .not. allocated(error), label//": case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), label//": the floor is read")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        do while (sim%time < tend)
            call advance(sim, min(stable_time_step(sim), tend - sim%time), error)
            if (allocated(error)) then
                call check(suite, .false., label//": run failed: "//error%message)
                return
            end if
        end do
        s = sum(sim%particles%mass*sim%particles%u(1, :))/sum(sim%particles%mass)
        lift = maxval(sim%particles%u(2, :))
        lowest = minval(sim%particles%x(2, :) - sim%particles%lp(2, :))
        if (mu < tan(theta)) then
            s_exact = 0.5_wp*g*(sin(theta) - mu*cos(theta))*tend**2
            call check_close(suite, s, s_exact, 0.02_wp*s_exact, &
                label//": slide s = g (sin - mu cos) t^2 / 2 within 2 %")
            print "(a,2(a,es11.4))", label, ": s = ", s, ", error ", s/s_exact - 1
        else
            call check(suite, abs(s) < 2.0e-3_wp*s_free, label// &
                ": the block sticks (|s| < 0.2 % of the frictionless slide)")
            print "(a,a,es11.4)", label, ": s = ", s
        end if
        call check(suite, lift < 1.0e-3_wp, label//": the block does not lift off")
        call check(suite, lowest > floor_y - 1.0e-3_wp, label// &
            ": no particle domain sinks more than 1 mm into the floor")
    end subroutine run_block

end program test_terrain_slide
