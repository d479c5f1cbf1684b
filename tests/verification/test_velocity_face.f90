!> Verification: a face of prescribed velocity (domain.boundaries.<face>.type = "velocity").
!>
!> A laterally confined elastic column (sliding sides and base, 2D, and 3D with z up) of
!> height H = 1 m, E = 1 MPa, nu = 0.3, rho = 1000, no gravity, compressed by its top face
!> moving down at v = 4e-4 m/s for 2.5 s (about 90 P-wave transits of the column: the wave of
!> the sudden start, rho c v, is about 1 % of the final stress). Quasi-static closed form:
!> the strain e = v t / H is uniform, s_yy = -M e with the confined modulus
!> M = E (1 - nu) / ((1 + nu) (1 - 2 nu)), s_xx = nu / (1 - nu) s_yy. Checked: the mean stress
!> of the particles within 3 %, the reaction of the top face (history.csv's column, the impulse
!> the face gives its nodes / dt) against s_yy A within 3 %, its work (booked as work of the
!> loads) against the stored energy M e^2 H A / 2 within 3 %, and the energy residual below
!> 1 % of that work: the energy of a run with a moving face closes. The sliding faces book the
!> force on the component they hold: the base's balances the top's, each wall's is -s_xx H.
program test_velocity_face
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        energy_residual
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "velocity_face")
    call run_column("2D", 2)
    call run_column("3D", 3)
    call asymmetric()
    call finish(suite)

contains

    subroutine run_column(label, dim)
        character(len=*), intent(in) :: label
            !! name of the run in messages
        integer, intent(in) :: dim
            !! space dimensions

        real(wp), parameter :: height = 1.0_wp, young = 1.0e6_wp, nu = 0.3_wp, speed = 4.0e-4_wp
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        character(len=:), allocatable :: geometry
        real(wp) :: modulus, strain, exact, syy, sxx, mass, section, reaction, stored
        integer :: p

        if (dim == 2) then
            geometry = '"domain": {"nx": 2, "ny": 10, "dx": 0.1, "boundaries": {"xmin": '// &
                '"sliding", "xmax": "sliding", "ymin": "sliding", "ymax": {"type": ' // &
                '"velocity", "velocity": [0, -4e-4]}}}, "bodies": [{"material": "m", ' // &
                '"min": [0, 0], "max": [0.2, 1.0]}], "gravity": [0, 0], '
            section = 0.2_wp
        else
            geometry = '"domain": {"nx": 2, "ny": 2, "nz": 10, "dx": 0.1, "boundaries": '// &
                '{"xmin": "sliding", "xmax": "sliding", "ymin": "sliding", "ymax": '// &
                '"sliding", "zmin": "sliding", "zmax": {"type": "velocity", "velocity": '// &
                '[0, 0, -4e-4]}}}, "bodies": [{"material": "m", "min": [0, 0, 0], '// &
                '"max": [0.2, 0.2, 1.0]}], "gravity": [0, 0, 0], '
            section = 0.04_wp
        end if
        call read_case_string('{"name": "column", '//geometry// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "linear_elastic", '// &
            '"E": 1e6, "nu": 0.3, "rho": 1000}], '// &
            '"solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
            '"time": {"tend": 2.5, "cfl": 0.5}}', case, error, "column")
        call check(suite, .not. allocated(error), label//": case is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call new_simulation(sim, case, error)
        if (allocated(error)) return
        do while (sim%time < case%time%tend)
            call advance(sim, stable_time_step(sim), error)
            if (allocated(error)) then
                call check(suite, .false., label//": run failed: "//error%message)
                return
            end if
        end do
        modulus = young*(1 - nu)/((1 + nu)*(1 - 2*nu))
        strain = speed*sim%time/height
        exact = -modulus*strain
        syy = 0.0_wp
        sxx = 0.0_wp
        mass = 0.0_wp
        do p = 1, sim%particles%n
            syy = syy + sim%particles%mass(p)*sim%particles%stress(dim, p)
            sxx = sxx + sim%particles%mass(p)*sim%particles%stress(1, p)
            mass = mass + sim%particles%mass(p)
        end do
        syy = syy/mass
        sxx = sxx/mass
        call check_close(suite, syy, exact, 0.03_wp*abs(exact), &
            label//": mean s_vertical = -M v t / H within 3 %")
        call check_close(suite, sxx, nu/(1 - nu)*exact, 0.03_wp*abs(nu/(1 - nu)*exact), &
            label//": mean s_xx = nu/(1-nu) s_vertical within 3 %")
        reaction = sim%face_reaction(dim, 2, dim)
        call check_close(suite, reaction, exact*section, 0.03_wp*abs(exact*section), &
            label//": reaction of the top face = s A within 3 %")
        call check(suite, all(abs(sim%face_reaction(1:dim - 1, 2, dim)) <= 1.0e-6_wp*abs(reaction)), &
            label//": no tangential reaction")
        ! the sliding faces hold their normal component: the base carries the top's load, the
        ! walls s_xx H per unit width (3D: times the width 0.2 m), none tangential
        call check_close(suite, sim%face_reaction(dim, 1, dim), -reaction, 0.03_wp*abs(reaction), &
            label//": the sliding base's reaction balances the top's within 3 %")
        call check_close(suite, sim%face_reaction(1, 1, 1), -nu/(1 - nu)*exact*height &
            *section/0.2_wp, 0.03_wp*abs(nu/(1 - nu)*exact*height*section/0.2_wp), &
            label//": the xmin wall's reaction = -s_xx H (per width) within 3 %")
        call check_close(suite, sim%face_reaction(1, 2, 1), -sim%face_reaction(1, 1, 1), &
            1.0e-9_wp*abs(sim%face_reaction(1, 1, 1)), label//": the two walls balance")
        call check(suite, all(sim%face_reaction(2:dim, :, 1) == 0.0_wp) .and. &
            all(sim%face_reaction(1:dim - 1, 1, dim) == 0.0_wp), &
            label//": a sliding face books its normal component only")
        stored = 0.5_wp*modulus*strain**2*height*section
        call check_close(suite, sim%energy%loads, stored, 0.03_wp*stored, &
            label//": work of the face = M e^2 H A / 2 within 3 %")
        call check_close(suite, sim%energy%elastic, stored, 0.03_wp*stored, &
            label//": stored elastic energy = M e^2 H A / 2 within 3 %")
        call check(suite, abs(energy_residual(sim%energy)) < 0.01_wp*sim%energy%loads, &
            label//": energy residual below 1 % of the work of the face")
        print "(a,5(a,es10.3))", label, ": s error ", syy/exact - 1, ", s_xx error ", &
            sxx/(nu/(1 - nu)*exact) - 1, ", reaction error ", reaction/(exact*section) - 1, &
            ", work error ", sim%energy%loads/stored - 1, ", residual / work ", &
            energy_residual(sim%energy)/sim%energy%loads
    end subroutine run_column

    !> A column against one sliding wall (xmin; xmax free), on a sliding base, pressed by a
    !> velocity face: at rest the reactions of all faces balance, and the corner nodes' x
    !> component, held by the wall and by the top, is booked once.
    subroutine asymmetric()
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: rx, ry

        call read_case_string('{"domain": {"nx": 4, "ny": 10, "dx": 0.1, "boundaries": ' &
            //'{"xmin": "sliding", "ymin": "sliding", "ymax": {"type": "velocity", ' &
            //'"velocity": [0, -4e-4]}}}, "particles": {"ppc": 2}, "materials": [{"name": ' &
            //'"m", "type": "linear_elastic", "E": 1e6, "nu": 0.3, "rho": 1000}], "bodies": ' &
            //'[{"material": "m", "min": [0, 0], "max": [0.2, 1.0]}], "gravity": [0, 0], ' &
            //'"time": {"tend": 2.5, "cfl": 0.5}, "damping": {"type": "local", "value": 0.2}}', &
            case, error)
        if (.not. allocated(error)) call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), "one-wall column starts")
        if (allocated(error)) return
        do while (sim%time < case%time%tend - 1.0e-12_wp .and. .not. allocated(error))
            call advance(sim, min(stable_time_step(sim), case%time%tend - sim%time), error)
        end do
        rx = sum(sim%face_reaction(1, :, :))
        ry = sum(sim%face_reaction(2, :, :))
        call check(suite, abs(rx) < 0.02_wp*abs(sim%face_reaction(1, 1, 1)) .and. &
            abs(sim%face_reaction(1, 1, 1)) > 0.0_wp, "one wall: the x reactions balance " &
            //"within 2 % of the wall's (the corner booked once)")
        call check(suite, abs(ry) < 0.02_wp*abs(sim%face_reaction(2, 1, 2)), &
            "one wall: the y reactions balance within 2 % of the base's")
    end subroutine asymmetric

end program test_velocity_face
