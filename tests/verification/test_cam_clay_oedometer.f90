!> Verification: Modified Cam Clay in a run, an oedometer (1D compression) of a normally
!> consolidated clay.
!>
!> A column 1 m high and 0.25 m wide (1 x 4 cells of 0.25 m, 2 x 2 particles per cell, cpGIMP,
!> MUSL), sliding sides, a fixed base and a top face pushed down at 0.05 m/s for 2 s (10 % of
!> its height), no gravity. The clay (M = 1.2, lambda = 0.2, kappa = 0.04, e0 = 1, nu = 0.3)
!> starts from an isotropic 100 kPa, normally consolidated (pc = p0).
!>
!> What the run must keep, whatever the path the oedometer takes (the elements of
!> test_mpm_material_cam_clay check the paths of the triaxial tests against their closed
!> forms):
!> - the volume law, per particle: -ln(V / V0) = kappa* ln(p / p0) + (lambda* - kappa*)
!>   ln(pc / pc0), the elastic and plastic volume changes of the model added up; the strain
!>   increments of the grid add up to the logarithmic strain to second order in the step
!>   (8e-6 here, on 2026-12-07; the check takes 5e-5, 0.05 % of the strain);
!> - loading on the yield surface: pc = p (1 + eta^2 / M^2) for the particles still yielding
!>   at the end (all but those a wave has just unloaded: at least 3/4);
!> - the stiffness grows with p, and the time step with it: the last step over the first is
!>   sqrt(max p at the start / max p at the end) (the wave speed goes as sqrt(p)), within 1 %;
!> - the energy balance closes to 1 % of the work of the top face.
program test_cam_clay_oedometer
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step, &
        start_energy_balance, energy_residual
    use mpm_stress, only: mean_and_deviator
    implicit none

    real(wp), parameter :: m_csl = 1.2_wp, lambda_s = 0.1_wp, kappa_s = 0.02_wp, p0 = 1.0e5_wp
    type(test_suite_type) :: suite
    type(case_type) :: case
    type(simulation_type) :: sim
    type(error_type), allocatable :: error
    real(wp) :: dt_first, dt_last, p_first, p_last, worst_volume, eps_v, mean, dev(4), radius
    real(wp) :: p, q, on_surface, residual, work
    integer :: i, n_on

    call new_suite(suite, "cam_clay_oedometer")
    call read_case_string('{"name": "oedometer", "domain": {"nx": 1, "ny": 4, "dx": 0.25, '// &
        '"boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": "fixed", '// &
        '"ymax": {"type": "velocity", "velocity": [0, -0.05]}}}, "particles": {"ppc": 2}, '// &
        '"materials": [{"name": "clay", "type": "cam_clay", "M": 1.2, "lambda": 0.2, '// &
        '"kappa": 0.04, "e0": 1.0, "nu": 0.3, "rho": 1800}], "bodies": [{"material": "clay", '// &
        '"min": [0, 0], "max": [0.25, 1.0]}], "gravity": [0, 0], '// &
        '"solver": {"scheme": "MUSL", "shape_function": "cpgimp"}, '// &
        '"time": {"tend": 2.0, "cfl": 0.5}}', case, error, "oedometer")
    call check(suite, .not. allocated(error), "case is valid")
    if (allocated(error)) then
        print "(a)", error%message
        call finish(suite)
    end if
    call new_simulation(sim, case, error)
    call check(suite, .not. allocated(error), "simulation starts")
    if (allocated(error)) call finish(suite)
    do i = 1, sim%particles%n
        sim%particles%stress(:, i) = [-p0, -p0, -p0, 0.0_wp]
    end do
    call start_energy_balance(sim)
    p_first = max_mean_stress()
    dt_first = stable_time_step(sim)
    dt_last = dt_first
    do while (sim%time < case%time%tend)
        dt_last = stable_time_step(sim)
        p_last = max_mean_stress()
        call advance(sim, dt_last, error)
        if (allocated(error)) then
            call check(suite, .false., "run failed: "//error%message)
            call finish(suite)
        end if
    end do

    worst_volume = 0.0_wp
    n_on = 0
    do i = 1, sim%particles%n
        call mean_and_deviator(sim%particles%stress(:, i), mean, dev, radius)
        p = -mean
        q = sqrt(3.0_wp)*radius
        eps_v = -log(sim%particles%volume(i)/sim%particles%volume0(i))
        worst_volume = max(worst_volume, abs(eps_v - kappa_s*log(p/p0) &
            - (lambda_s - kappa_s)*log(sim%particles%state(2, i)/p0)))
        on_surface = sim%particles%state(2, i)/(p*(1.0_wp + (q/p)**2/m_csl**2)) - 1.0_wp
        if (abs(on_surface) < 1.0e-6_wp) n_on = n_on + 1
    end do
    call check(suite, maxval(-log(sim%particles%volume(1:sim%particles%n) &
        /sim%particles%volume0(1:sim%particles%n))) > 0.09_wp, "the column compressed ~10 %")
    call check_close(suite, worst_volume, 0.0_wp, 5.0e-5_wp, "per particle: -ln(V/V0) = " &
        //"kappa* ln(p/p0) + (lambda* - kappa*) ln(pc/pc0)")
    call check(suite, 4*n_on >= 3*sim%particles%n, "at least 3/4 of the particles on the " &
        //"yield surface, pc = p (1 + eta^2 / M^2)")
    call check(suite, p_last > 2.0_wp*p_first, "the clay consolidated: p more than doubled")
    call check_close(suite, dt_last/dt_first, sqrt(p_first/p_last), 0.01_wp*sqrt(p_first/p_last), &
        "the time step follows the stiffness: dt_last / dt_first = sqrt(p_first / p_last)")
    residual = energy_residual(sim%energy)
    work = abs(sim%energy%loads) + abs(sim%energy%boundary)
    call check(suite, abs(residual) < 0.01_wp*work, "energy residual below 1 % of the work of " &
        //"the top face")
    print "(a,4(a,es10.3))", "oedometer", ": volume law ", worst_volume, ", p_end / p0 ", &
        p_last/p0, ", dt_last / dt_first ", dt_last/dt_first, ", residual / work ", residual/work
    print "(a,i0,a,i0)", "particles on the yield surface: ", n_on, " of ", sim%particles%n
    call finish(suite)

contains

    !> The largest mean stress of the particles [Pa].
    real(wp) function max_mean_stress()
        integer :: j

        max_mean_stress = 0.0_wp
        do j = 1, sim%particles%n
            max_mean_stress = max(max_mean_stress, -sum(sim%particles%stress(1:3, j))/3.0_wp)
        end do
    end function max_mean_stress

end program test_cam_clay_oedometer
