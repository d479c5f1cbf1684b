!> Verification: a block sliding on a frictional floor under a tilted gravity vector
!> (../shared/REFERENCES.md section 4).
!>
!> Gravity g (sin theta, -cos theta), theta = 30 deg, the floor (ymin) frictional with Coulomb
!> coefficient mu. Exact: s(t) = g (sin theta - mu cos theta) t^2 / 2 while mu < tan theta, and
!> the block sticks for mu >= tan theta. Checked: the mean displacement along the floor within
!> 2 % of s(t) for mu = 0, 0.2, 0.4, and below 0.2 % of the frictionless slide for mu = 0.6.
!> Energies: the friction work within 2 % (the band of the slide, whose friction it is) of
!> mu N s, N = m g cos(theta) the normal load, s the slide; no friction work without friction;
!> for the sticking block, below 0.2 % of the frictionless gravity work (a block at rest does
!> no friction work) and not above the work of gravity; the residual below 2 % of the work of
!> gravity (sticking: 0.2 % of that of the frictionless slide, the band of its displacement);
!> the mean lift of the block below a tenth of the contact's gap tolerance.
!> The block is flat (0.2 m x 0.04 m): the resultant of its weight falls well inside the middle
!> third of its base, so it slides or sticks without tipping, as the analytic solution assumes.
program test_sliding_block
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        energy_residual
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: g = 9.81_wp, tend = 0.5_wp
    real(wp) :: theta, s_free

    call new_suite(suite, "sliding_block")
    theta = acos(-1.0_wp)/6
    s_free = 0.5_wp*g*sin(theta)*tend**2
    call run_block(0.0_wp, "0.0")
    call run_block(0.2_wp, "0.2")
    call run_block(0.4_wp, "0.4")
    call run_block(0.6_wp, "0.6")
    ! a smaller step must not change the friction (the normal impulse is averaged over a fixed
    ! time, not a fixed number of steps)
    call run_block(0.4_wp, "0.4", "0.2")
    call run_block(0.6_wp, "0.6", "0.2")
    call finish(suite)

contains

    subroutine run_block(mu, mu_text, cfl_text)
        real(wp), intent(in) :: mu
        character(len=*), intent(in) :: mu_text
        character(len=*), intent(in), optional :: cfl_text

        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        character(len=64) :: gravity
        character(len=:), allocatable :: cfl, label
        real(wp) :: s, s_exact, lift, mass, friction, gravity_work, lift_mean

        cfl = "0.5"
        if (present(cfl_text)) cfl = cfl_text
        label = "mu = "//mu_text//", cfl "//cfl

        write (gravity, "(a,es23.16,a,es23.16,a)") "[", g*sin(theta), ", ", -g*cos(theta), "]"
        call read_case_string('{"name": "block", "domain": {"nx": 60, "ny": 10, "dx": 0.02, '// &
            '"boundaries": {"ymin": {"type": "frictional", "mu": '//mu_text//'}}}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
            '"E": 1e8, "nu": 0.3, "rho": 2000}], "bodies": [{"material": "m", '// &
            '"min": [0.1, 0], "max": [0.3, 0.04]}], "gravity": '//trim(gravity)//', '// &
            '"solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
            '"time": {"tend": 0.5, "cfl": '//cfl//'}}', case, error, "block")
        call check(suite, .not. allocated(error), label//": case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        if (allocated(error)) return
        do while (sim%time < tend)
            call advance(sim, min(stable_time_step(sim), tend - sim%time), error)
            if (allocated(error)) then
                call check(suite, .false., label//": run failed: "//error%message)
                return
            end if
        end do
        s = sum(sim%particles%mass*sim%particles%u(1, :))/sum(sim%particles%mass)
        lift = maxval(sim%particles%u(2, :))
        mass = sum(sim%particles%mass)
        gravity_work = -sim%energy%potential
        friction = mu*mass*g*cos(theta)*s
        if (mu == 0.0_wp) then
            call check(suite, sim%energy%friction == 0.0_wp, label//": no friction work")
        else if (mu < tan(theta)) then
            call check_close(suite, sim%energy%friction, friction, 0.02_wp*friction, &
                label//": friction work mu N s within 2 %")
        else
            call check(suite, abs(sim%energy%friction) < 2.0e-3_wp*mass*g*sin(theta)*s_free, &
                label//": sticking: friction work below 0.2 % of the frictionless gravity work")
            ! friction dissipates what gravity put in, never more (a block that lifted off
            ! and crept had it book 16.2 mJ against 13.6 mJ of gravity work)
            call check(suite, sim%energy%friction <= gravity_work, &
                label//": sticking: friction work not above the work of gravity")
        end if
        ! the block settles on the floor: its mean lift stays a tenth of the gap the contact
        ! counts as touching (0.001 dx; a one-sided constraint on the moves ratchets the
        ! ringing block up to that gap), its elastic settlement being ~ 1e-7 m
        lift_mean = sum(sim%particles%mass*sim%particles%u(2, :))/mass
        call check(suite, abs(lift_mean) < 1.0e-4_wp*0.02_wp, &
            label//": mean lift below a tenth of the contact's gap tolerance")
        print "(a,a,es11.4)", label, ": mean lift ", lift_mean
        if (mu < tan(theta)) then
            call check(suite, abs(energy_residual(sim%energy)) < 0.02_wp*gravity_work, &
                label//": energy residual below 2 % of the gravity work")
        else
            ! the block at rest: gravity did almost no work; the band of its slide
            call check(suite, abs(energy_residual(sim%energy)) < 2.0e-3_wp*mass*g*sin(theta) &
                *s_free, label//": energy residual below 0.2 % of the frictionless gravity work")
        end if
        print "(a,3(a,es11.4))", label, ": friction work ", sim%energy%friction, &
            ", mu N s ", friction, ", residual / gravity work ", &
            energy_residual(sim%energy)/max(gravity_work, tiny(1.0_wp))
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
        ! the block stays on the floor: no particle moves up by more than elastic deformation
        call check(suite, lift < 1.0e-3_wp, label//": the block does not lift off")
    end subroutine run_block

end program test_sliding_block
