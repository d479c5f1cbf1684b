!> A rigid rotation leaves the cpGIMP particle domains as they are (issue 19).
!>
!> A free elastic block spins as a rigid body (no gravity, the velocity field omega x (x - c)
!> given to its particles) through a quarter turn. Its deformation gradients then are close
!> to a rotation by 90 degrees (checked: |F_12|, |F_21| near 1 and |F^T F - I| < 0.05; the
!> spin stretches the block by rho omega^2 r^2 / E ~ 1e-3, and the discrete rotation of USL
!> adds 7e-3, of MUSL 2.6e-2), and the half-sizes of the particle domains must stay those of
!> the start within that stretch (|lp/lp0 - 1| <= |F^T F - I|, about twice the change of a
!> length). The former update lp0 |F_aa| shrank every domain to 7 % of its size by then
!> (nearly the weights of linear hats), which made the free end of a hanging cantilever
!> unstable (docs/accuracy-vs-cost.md). The same spin with CPDI (whose domain is the image of
!> the initial box under F, mpm_shape_cpdi) checks that its full stencils carry a block
!> through a quarter turn as a rigid body too.
program test_gimp_rotation
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, start_energy_balance
    use mpm_particle_domain, only: domain_half_sizes
    implicit none

    real(wp), parameter :: omega = 1.0_wp
        !! spin [rad/s]
    real(wp), parameter :: centre(2) = [0.5_wp, 0.5_wp]
        !! centre of the block [m]
    real(wp), parameter :: pi = acos(-1.0_wp)

    type(test_suite_type) :: suite
    character(len=8) :: scheme(2) = [character(len=8) :: "USL", "MUSL"]
    integer :: k

    call new_suite(suite, "gimp_rotation")
    do k = 1, size(scheme)
        call quarter_turn(trim(scheme(k)), "cpgimp")
    end do
    do k = 1, size(scheme)
        call quarter_turn(trim(scheme(k)), "cpdi")
    end do
    call finish(suite)

contains

    subroutine quarter_turn(scheme, shape)
        character(len=*), intent(in) :: scheme
            !! USL or MUSL
        character(len=*), intent(in) :: shape
            !! solver.shape_function

        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        integer :: p, steps, k
        real(wp) :: dt, r(2), size_change, stretch, ftf(2, 2), turned, lp(2)
        character(len=100) :: values

        call read_case_string('{"name": "spin", "domain": {"nx": 50, "ny": 50, "dx": 0.02}, '// &
            '"particles": {"ppc": 2}, "materials": [{"name": "m", "type": "neo_hookean", '// &
            '"E": 1e4, "nu": 0.3, "rho": 1000}], "bodies": [{"material": "m", '// &
            '"min": [0.4, 0.4], "max": [0.6, 0.6]}], "solver": {"scheme": "'//scheme// &
            '", "shape_function": "'//shape//'"}, "time": {"tend": 2.0, "dt": 1e-3}}', case, &
            error, "spin")
        if (allocated(error)) then
            call check(suite, .false., scheme//" "//shape//": case: "//error%message)
            return
        end if
        call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), scheme//" "//shape//": set-up")
        if (allocated(error)) return
        do p = 1, sim%particles%n
            r = sim%particles%x(:, p) - centre
            sim%particles%v(:, p) = omega*[-r(2), r(1)]
        end do
        call start_energy_balance(sim)
        ! a quarter turn in steps of about 1 ms (c = 3.7 m/s: CFL 0.2)
        steps = nint(0.5_wp*pi/omega/1.0e-3_wp)
        dt = 0.5_wp*pi/omega/real(steps, wp)
        do k = 1, steps
            call advance(sim, dt, error)
            if (allocated(error)) exit
        end do
        if (allocated(error)) then
            call check(suite, .false., scheme//" "//shape//": runs a quarter turn: "//error%message)
            return
        end if
        call check(suite, .true., scheme//" "//shape//": runs a quarter turn")
        size_change = 0.0_wp
        stretch = 0.0_wp
        turned = huge(1.0_wp)
        do p = 1, sim%particles%n
            associate (f => sim%particles%f(:, :, p))
                ftf = matmul(transpose(f), f)
                stretch = max(stretch, maxval(abs(ftf - reshape([1, 0, 0, 1], [2, 2]))))
                turned = min(turned, abs(f(1, 2)), abs(f(2, 1)))
            end associate
            call domain_half_sizes(sim%particles%f(:, :, p), sim%particles%lp0(:, p), 2, lp)
            size_change = max(size_change, maxval(abs(lp/sim%particles%lp0(:, p) - 1.0_wp)))
        end do
        write (values, "(3(a,es9.2))") " (min |F_12|, |F_21| ", turned, ", |F^T F - I| ", &
            stretch, ", |lp/lp0 - 1| ", size_change
        call check(suite, turned > 0.95_wp .and. stretch < 0.05_wp, &
            scheme//" "//shape//": F is a rotation by a quarter turn"//trim(values)//")")
        call check(suite, size_change < max(stretch, 1.0e-3_wp), &
            scheme//" "//shape//": the particle domains keep their size"//trim(values)//")")
    end subroutine quarter_turn

end program test_gimp_rotation
