!> Verification: the geostatic initial stress (initial_stress.type = "k0") of a layered
!> column, against the closed form, and at rest.
!>
!> Two layers between sliding walls on a fixed base: sand (Mohr-Coulomb, rho 2000, phi 30,
!> K0 = 1 - sin 30 = 0.5) from 0 to 4 m, clay above it (linear elastic, rho 1800, nu 0.3,
!> K0 = nu / (1 - nu)) to 8 m, the clay given as a polygon; gravity 9.81 down the last axis
!> (2D: y; 3D: z). Closed form: s_v = -rho_c g (8 - y) in the clay, -rho_c g 4 - rho_s g
!> (4 - y) in the sand, s_h = K0 s_v, no shear. Checked: every particle's stress equals it
!> to 1e-12 (relative to the largest); the stored elastic energy at the start equals the
!> closed form integrated over the particles; 200 undamped steps later the kinetic energy is
!> below 1e-9 of it (the column starts in equilibrium); and the same column without the
!> initial stress reaches more than 1e-3 of it in those steps (so the check can fail). A
!> given k0 replaces the materials' own.
program test_k0_column
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_solver, only: simulation_type, new_simulation, advance, stable_time_step
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "k0_column")
    call column("2D", 2, '"initial_stress": {"type": "k0"}, ', 0.5_wp, 0.3_wp/0.7_wp)
    call column("3D", 3, '"initial_stress": {"type": "k0"}, ', 0.5_wp, 0.3_wp/0.7_wp)
    call column("2D, k0 given", 2, '"initial_stress": {"type": "k0", "k0": 0.8}, ', 0.8_wp, &
        0.8_wp)
    call column("2D, no initial stress", 2, "", -1.0_wp, -1.0_wp)
    call finish(suite)

contains

    subroutine column(label, dim, initial, k0_sand, k0_clay)
        character(len=*), intent(in) :: label, initial
        integer, intent(in) :: dim
        real(wp), intent(in) :: k0_sand, k0_clay
            !! expected K0 of each layer; negative: no initial stress

        real(wp), parameter :: g = 9.81_wp, rho_s = 2000.0_wp, rho_c = 1800.0_wp
        character(len=:), allocatable :: text, geometry
        type(case_type) :: case
        type(simulation_type) :: sim
        type(error_type), allocatable :: error
        real(wp) :: y, sv, k0, exact(6), worst, scale, kinetic_max, elastic0
        integer :: p, k, n

        if (dim == 2) then
            geometry = '"domain": {"nx": 4, "ny": 20, "dx": 0.5, "boundaries": {"xmin": ' &
                //'"sliding", "xmax": "sliding", "ymin": "fixed"}}, "bodies": [{"material": ' &
                //'"sand", "min": [0, 0], "max": [2, 4]}, {"material": "clay", "polygon": ' &
                //'[[0, 4], [2, 4], [2, 8], [0, 8]]}], "gravity": [0, -9.81], '
        else
            geometry = '"dimension": 3, "domain": {"nx": 2, "ny": 2, "nz": 20, "dx": 0.5, ' &
                //'"boundaries": {"xmin": "sliding", "xmax": "sliding", "ymin": "sliding", ' &
                //'"ymax": "sliding", "zmin": "fixed"}}, "bodies": [{"material": "sand", ' &
                //'"min": [0, 0, 0], "max": [1, 1, 4]}, {"material": "clay", "min": [0, 0, 4], ' &
                //'"max": [1, 1, 8]}], "gravity": [0, 0, -9.81], '
        end if
        text = '{"name": "k0", '//geometry//initial//'"particles": {"ppc": 2}, "materials": ' &
            //'[{"name": "clay", "type": "linear_elastic", "E": 2e7, "nu": 0.3, "rho": 1800}, ' &
            //'{"name": "sand", "type": "mohr_coulomb", "E": 4e7, "nu": 0.3, "rho": 2000, ' &
            //'"phi": 30, "c": 0, "psi": 0}], "solver": {"scheme": "MUSL", "shape_function": ' &
            //'"cpgimp"}, "time": {"tend": 1, "cfl": 0.5}, "damping": {"type": "none"}}'
        call read_case_string(text, case, error, label)
        if (.not. allocated(error)) call new_simulation(sim, case, error)
        call check(suite, .not. allocated(error), label//": set-up")
        if (allocated(error)) then
            print '(a)', error%message
            return
        end if
        n = sim%particles%n
        if (k0_sand > 0.0_wp) then
            ! the closed form at every particle
            worst = 0.0_wp
            scale = rho_c*g*4.0_wp + rho_s*g*4.0_wp
            elastic0 = 0.0_wp
            do p = 1, n
                y = sim%particles%x(dim, p)
                if (y > 4.0_wp) then
                    sv = -rho_c*g*(8.0_wp - y)
                    k0 = k0_clay
                else
                    sv = -rho_c*g*4.0_wp - rho_s*g*(4.0_wp - y)
                    k0 = k0_sand
                end if
                exact = 0.0_wp
                exact(1:3) = k0*sv
                exact(dim) = sv
                worst = max(worst, maxval(abs(sim%particles%stress(:, p) &
                    - exact(1:size(sim%particles%stress, 1))))/scale)
                elastic0 = elastic0 + sim%particles%volume(p)*elastic_density(exact, &
                    merge(2.0e7_wp, 4.0e7_wp, y > 4.0_wp), 0.3_wp)
            end do
            print '(a, es9.2)', "  "//label//": largest stress error / largest stress", worst
            call check(suite, worst < 1.0e-12_wp, label//": stresses of the closed form " &
                //"(vertical: the weight above; horizontal: K0 times it)")
            call check(suite, abs(sim%energy%elastic - elastic0) < 1.0e-9_wp*elastic0, &
                label//": the stored elastic energy of those stresses")
        else
            call check(suite, all(sim%particles%stress == 0.0_wp), label//": no stress")
            elastic0 = 1190.56_wp   ! the 2D column's, for the scale of the kinetic energy
        end if
        kinetic_max = 0.0_wp
        do k = 1, 200
            call advance(sim, stable_time_step(sim), error)
            if (allocated(error)) exit
            kinetic_max = max(kinetic_max, sim%energy%kinetic)
        end do
        call check(suite, .not. allocated(error), label//": runs")
        print '(a, es9.2)', "  "//label//": largest kinetic / initial elastic energy", &
            kinetic_max/elastic0
        if (k0_sand > 0.0_wp) then
            call check(suite, kinetic_max < 1.0e-9_wp*elastic0, label//": at rest (largest " &
                //"kinetic energy of 200 steps below 1e-9 of the elastic energy)")
        else
            call check(suite, kinetic_max > 1.0e-3_wp*elastic0, label//": without it the " &
                //"column moves (kinetic energy above 1e-3 of the K0 column's elastic energy)")
        end if
    end subroutine column

    !> Elastic energy per unit volume of normal stresses (Voigt, no shear) in an isotropic
    !> solid: (s1^2 + s2^2 + s3^2 - 2 nu (s1 s2 + s2 s3 + s3 s1)) / (2 E).
    pure real(wp) function elastic_density(s, young, poisson)
        real(wp), intent(in) :: s(6), young, poisson

        elastic_density = (sum(s(1:3)**2) - 2.0_wp*poisson*(s(1)*s(2) + s(2)*s(3) &
            + s(3)*s(1)))/(2.0_wp*young)
    end function elastic_density

end program test_k0_column
