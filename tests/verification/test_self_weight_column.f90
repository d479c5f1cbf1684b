!> Verification: laterally confined column under its own weight (../shared/REFERENCES.md s. 2).
!>
!> Column of height H = 1 m between sliding walls on a fixed base (2D, and 3D with z up), rho = 1800, E = 1 MPa,
!> nu = 0.3, gravity 9.81, brought to rest by local damping. Exact small-strain solution:
!> s_yy = -rho g (H - y), s_xx = nu / (1 - nu) s_yy. Checked: the stress of the lowest row
!> of particles within 2 % of the exact value at their height, with cpGIMP and MUSL.
!> Energies at rest: the stored elastic energy within 4 % (twice the stress band: w ~ sigma^2)
!> of the closed form W = (rho g)^2 H^3 A / (6 M) (A the section, M = E (1 - nu) / ((1 + nu)
!> (1 - 2 nu)) the confined modulus); gravity did 2 W of work (Clapeyron), so the damping
!> removed W, within the same band; the residual of the balance below 1 % of W.
!> Then save_state / load_state: a new undamped run started from the saved equilibrium stays
!> at rest (its particles carry the geostatic stress), and the state round trip is exact.
program test_self_weight_column
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        energy_residual
    use mpm_state, only: save_state
    use mpm_setup, only: start_simulation
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "self_weight_column")
    call run_column("local", '"damping": {"type": "local", "value": 0.15}', 2)
    call run_column("kinetic", '"damping": {"type": "kinetic"}', 2)
    call run_column("3D kinetic", '"damping": {"type": "kinetic"}', 3)
    call finish(suite)

contains

    subroutine run_column(label, damping, dim)
        character(len=*), intent(in) :: label, damping
        integer, intent(in) :: dim

        real(wp), parameter :: height = 1.0_wp, rho = 1800.0_wp, g = 9.81_wp, nu = 0.3_wp
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: ymin, y0, exact, syy, sxx, mass_row, section, stored
        integer :: p

        character(len=:), allocatable :: geometry
        integer :: up

        if (dim == 2) then
            ! vertical axis y
            geometry = '"domain": {"nx": 4, "ny": 44, "dx": 0.025, "boundaries": {"xmin": '// &
                '"sliding", "xmax": "sliding", "ymin": "fixed"}}, "bodies": [{"material": '// &
                '"soil", "min": [0, 0], "max": [0.1, 1.0]}], "gravity": [0, -9.81], '
        else
            ! vertical axis z, a coarser grid: 2 x 2 x 22 cells of 5 cm
            geometry = '"domain": {"nx": 2, "ny": 2, "nz": 22, "dx": 0.05, "boundaries": '// &
                '{"xmin": "sliding", "xmax": "sliding", "ymin": "sliding", "ymax": "sliding", '// &
                '"zmin": "fixed"}}, "bodies": [{"material": "soil", "min": [0, 0, 0], '// &
                '"max": [0.1, 0.1, 1.0]}], "gravity": [0, 0, -9.81], '
        end if
        up = dim
        call read_case_string('{"name": "column", '//geometry// &
            '"particles": {"ppc": 2}, "materials": [{"name": "soil", "type": "linear_elastic", '// &
            '"E": 1e6, "nu": 0.3, "rho": 1800}], '// &
            '"solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
            '"time": {"tend": 3.0, "cfl": 0.5}, '//damping//'}', case, error, "column")
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
        ! lowest row of particles (initial y = dx / 4): mass-weighted mean stress
        ymin = minval(sim%particles%x(up, :) - sim%particles%u(up, :))
        syy = 0.0_wp
        sxx = 0.0_wp
        mass_row = 0.0_wp
        y0 = ymin
        do p = 1, sim%particles%n
            if (sim%particles%x(up, p) - sim%particles%u(up, p) < ymin + 1.0e-9_wp) then
                syy = syy + sim%particles%mass(p)*sim%particles%stress(up, p)
                sxx = sxx + sim%particles%mass(p)*sim%particles%stress(1, p)
                mass_row = mass_row + sim%particles%mass(p)
            end if
        end do
        syy = syy/mass_row
        sxx = sxx/mass_row
        exact = -rho*g*(height - y0)
        call check_close(suite, syy, exact, 0.02_wp*abs(exact), &
            label//": base stress s_yy within 2 %")
        call check_close(suite, sxx, nu/(1 - nu)*exact, 0.02_wp*abs(nu/(1 - nu)*exact), &
            label//": base stress s_xx = nu/(1-nu) s_yy within 2 %")
        section = 0.1_wp
        if (dim == 3) section = 0.01_wp
        stored = (rho*g)**2*height**3*section &
            /(6.0_wp*1.0e6_wp*(1 - nu)/((1 + nu)*(1 - 2*nu)))
        call check_close(suite, sim%energy%elastic, stored, 0.04_wp*stored, &
            label//": stored elastic energy (rho g)^2 H^3 A / (6 M) within 4 %")
        call check_close(suite, sim%energy%damping, stored, 0.04_wp*stored, &
            label//": damping work = gravity work - stored energy = W within 4 %")
        call check(suite, abs(energy_residual(sim%energy)) < 0.01_wp*stored, &
            label//": energy residual below 1 % of W")
        print "(a,3(a,es10.3))", label, ": elastic energy error ", sim%energy%elastic/stored - 1, &
            ", damping work error ", sim%energy%damping/stored - 1, ", residual / W ", &
            energy_residual(sim%energy)/stored
        call check(suite, sim%energy%kinetic < 1.0e-4_wp*sim%energy%strain, &
            label//": column at rest (kinetic energy < 1e-4 strain energy)")
        print "(a,2(a,es10.3))", label, ": base s_yy error ", syy/exact - 1, &
            ", s_xx error ", sxx/(nu/(1 - nu)*exact) - 1
        if (label == "local") call restart_from_state(sim)
    end subroutine run_column

    !> Save the equilibrium, start an undamped run from it, and check it stays at rest.
    subroutine restart_from_state(settled)
        type(simulation_type), intent(in) :: settled

        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        character(len=:), allocatable :: path
        character(len=256) :: tmpdir
        integer :: length, stat
        real(wp) :: ke_max, weight_work

        call get_environment_variable("TMPDIR", tmpdir, length, stat)
        if (stat /= 0 .or. length == 0) tmpdir = "/tmp"
        path = trim(tmpdir)//"/mpm_geo_test_column_state.h5"
        call save_state(path, settled%case, settled%particles, settled%time, &
            int(settled%step), error)
        call check(suite, .not. allocated(error), "save_state of the equilibrium")
        if (allocated(error)) return
        call read_case_string('{"name": "restart", "domain": {"nx": 4, "ny": 44, "dx": 0.025, '// &
            '"boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": "fixed"}}, '// &
            '"materials": [{"name": "soil", "type": "linear_elastic", '// &
            '"E": 1e6, "nu": 0.3, "rho": 1800}], "gravity": [0, -9.81], '// &
            '"load_state": "'//path//'", "time": {"tend": 0.5}}', case, error, "restart")
        call check(suite, .not. allocated(error), "restart case with load_state is valid")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        call start_simulation(sim, case, error)
        call check(suite, .not. allocated(error), "load_state into a new simulation")
        if (allocated(error)) return
        call check(suite, all(sim%particles%stress == settled%particles%stress) .and. &
            all(sim%particles%x == settled%particles%x), "state restores stress and positions")
        ke_max = 0.0_wp
        do while (sim%time < case%time%tend)
            call advance(sim, stable_time_step(sim), error)
            if (allocated(error)) return
            ke_max = max(ke_max, sim%energy%kinetic)
        end do
        ! scale: the work gravity did on the column while it settled; without its stresses
        ! the column would fall and turn a large part of that into kinetic energy
        weight_work = settled%energy%strain
        call check(suite, ke_max < 1.0e-4_wp*weight_work, &
            "undamped run from the saved equilibrium stays at rest")
        print "(a,es10.3)", "restart: max kinetic energy / settled strain energy ", &
            ke_max/weight_work
        open (newunit=length, file=path, status="old", iostat=stat)
        if (stat == 0) close (length, status="delete")
    end subroutine restart_from_state

end program test_self_weight_column
