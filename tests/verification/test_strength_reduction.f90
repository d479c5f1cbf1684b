!> Verification: the factor of safety by strength reduction (`strength_reduction`).
!>
!> The reduced strength: tan(phi) / F, c / F, the tensile strength / F, psi kept below the
!> reduced phi, F = 1 unchanged; a Mohr-Coulomb material's reduce_strength gives the same
!> return as a material built with the reduced values, an elastic one has nothing to reduce.
!>
!> The analysis: the 2:1 slope of Griffiths and Lane (1999) at a tenth of their resolution
!> (H = 5 m, H / dx = 10, c / (gamma H) = 0.05, phi = 20 deg; their factor of safety 1.4,
!> validation/slope_fos checks it at H / dx = 20 and 40). Bisection from [1, 2] to 0.05: the
!> factor_min trial holds and the factor_max one fails, every verdict is the criterion's on
!> the trial's own displacement and kinetic energy, each new factor is the middle of the
!> bracket so far, the final bracket is at most the tolerance wide and lies between 1.3 and
!> 1.7 (1.4 with the coarse grid's overestimate; 1.0 or 2.0 would mean the criterion never or
!> always fails), the table lists every trial and the case's own strength is unchanged. The
!> same slope holds at factor_max = 1.2: no factor, said so.
program test_strength_reduction
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_case, only: case_type, read_case_string
    use mpm_run, only: run_options_type
    use mpm_strength, only: strength_type, reduced_strength, degree
    use mpm_material_mohr_coulomb, only: mohr_coulomb_material_type, new_mohr_coulomb_material
    use mpm_material_elastic, only: elastic_material_type
    use mpm_strength_reduction, only: strength_reduction_result_type, run_strength_reduction, &
        trial_fails
    use mpm_filesystem, only: directory_exists, file_exists
    implicit none

    type(test_suite_type) :: suite
    character(len=*), parameter :: dir = "test_strength_reduction.tmp"

    call new_suite(suite, "strength_reduction")
    call reduced_values()
    call analysis()
    call finish(suite)

contains

    subroutine reduced_values()
        type(strength_type) :: s, r
        type(mohr_coulomb_material_type) :: a, b
        type(elastic_material_type) :: e
        real(wp) :: stress_a(4), stress_b(4), state_a(2), state_b(2)
        logical :: reduced

        s%friction = 30.0_wp*degree
        s%cohesion = 1.0e4_wp
        s%dilatancy = 10.0_wp*degree
        s%tension_cutoff = 2.0e3_wp
        s%friction_residual = 20.0_wp*degree
        s%cohesion_residual = 1.0e3_wp
        r = reduced_strength(s, 2.0_wp)
        call check_close(suite, tan(r%friction), tan(s%friction)/2.0_wp, 1.0e-14_wp, "tan(phi) / F")
        call check_close(suite, r%cohesion, 5.0e3_wp, 1.0e-14_wp, "c / F")
        call check_close(suite, r%tension_cutoff, 1.0e3_wp, 1.0e-14_wp, "tensile strength / F")
        call check_close(suite, tan(r%friction_residual), tan(s%friction_residual)/2.0_wp, &
            1.0e-14_wp, "residual tan(phi) / F")
        call check_close(suite, r%cohesion_residual, 500.0_wp, 1.0e-14_wp, "residual c / F")
        call check(suite, r%dilatancy == s%dilatancy, "psi below the reduced phi is kept")
        s%dilatancy = s%friction
        r = reduced_strength(s, 2.0_wp)
        call check(suite, r%dilatancy == r%friction, "an associated material stays associated")
        r = reduced_strength(s, 1.0_wp)
        call check(suite, r%friction == s%friction .and. r%cohesion == s%cohesion .and. &
            r%dilatancy == s%dilatancy, "F = 1 leaves the strength as it is")

        ! the material's reduction is the material built with the reduced strength
        s%dilatancy = 0.0_wp
        s%tension_cutoff = -1.0_wp
        call new_mohr_coulomb_material(a, 1.0e7_wp, 0.3_wp, 2000.0_wp, s)
        call a%reduce_strength(1.5_wp, reduced)
        call check(suite, reduced, "Mohr-Coulomb has a strength to reduce")
        call new_mohr_coulomb_material(b, 1.0e7_wp, 0.3_wp, 2000.0_wp, reduced_strength(s, 1.5_wp))
        stress_a = [-1.0e4_wp, -3.0e4_wp, -1.0e4_wp, 0.0_wp]
        stress_b = stress_a
        state_a = 0.0_wp
        state_b = 0.0_wp
        call a%update_stress(stress_a, [0.0_wp, -2.0e-3_wp, 0.0_wp, 1.0e-2_wp], [0.0_wp, 0.0_wp, &
            0.0_wp], 1.0e-3_wp, state_a)
        call b%update_stress(stress_b, [0.0_wp, -2.0e-3_wp, 0.0_wp, 1.0e-2_wp], [0.0_wp, 0.0_wp, &
            0.0_wp], 1.0e-3_wp, state_b)
        call check(suite, all(stress_a == stress_b) .and. all(state_a == state_b) .and. &
            state_a(1) > 0.0_wp, "reduced Mohr-Coulomb returns as one built reduced (plastic step)")
        call e%reduce_strength(1.5_wp, reduced)
        call check(suite, .not. reduced, "an elastic material has no strength to reduce")
    end subroutine reduced_values

    function slope_case(factor_max, tolerance) result(text)
        character(len=*), intent(in) :: factor_max, tolerance
        character(len=:), allocatable :: text

        ! H = 5 m, gamma = 2000 * 9.81, c = 0.05 gamma H = 4905 Pa
        text = '{"name": "srm", "domain": {"nx": 50, "ny": 12, "dx": 0.5, "boundaries": ' &
            //'{"xmin": "sliding", "xmax": "sliding", "ymin": "fixed"}}, "particles": {"ppc": 2}, ' &
            //'"materials": [{"name": "soil", "type": "mohr_coulomb", "E": 1e8, "nu": 0.3, ' &
            //'"rho": 2000, "phi": 20, "c": 4905, "psi": 0}], "bodies": [{"material": "soil", ' &
            //'"polygon": [[0, 0], [17.5, 0], [7.5, 5], [0, 5]]}], "gravity": [0, -9.81], ' &
            //'"initial_stress": {"type": "k0"}, "time": {"tend": 3, "cfl": 0.5}, ' &
            //'"damping": {"type": "local", "value": 0.1}, "output": {"interval": 3, ' &
            //'"directory": "'//dir//'"}, "progress": {"interval": 1000}, ' &
            //'"strength_reduction": {"factor_min": 1, "factor_max": '//factor_max &
            //', "tolerance": '//tolerance//', "displacement_limit": 0.05}}'
    end function slope_case

    real(wp) function cohesion(case)
        type(case_type), intent(in) :: case

        cohesion = -1.0_wp
        select type (law => case%materials(1)%law)
        type is (mohr_coulomb_material_type)
            cohesion = law%strength%cohesion
        end select
    end function cohesion

    subroutine analysis()
        type(case_type) :: case
        type(error_type), allocatable :: error
        type(run_options_type) :: options
        type(strength_reduction_result_type) :: outcome
        real(wp) :: low, high, c0
        integer :: k, unit, lines, ios
        logical :: consistent, halves
        character(len=200) :: line

        call execute_command_line("rm -rf '"//dir//"'")
        call read_case_string(slope_case("2", "0.05"), case, error)
        call check(suite, .not. allocated(error), "slope case reads")
        if (allocated(error)) return
        c0 = cohesion(case)
        options%quiet = .true.
        call run_strength_reduction(case, options, outcome, error)
        call check(suite, .not. allocated(error), "analysis runs")
        if (allocated(error)) then
            print "(a)", error%message
            return
        end if
        associate (t => outcome%trials)
            call check(suite, size(t) >= 7, "two bounds and five halvings from [1, 2] to 0.05")
            call check(suite, .not. t(1)%fails .and. t(1)%factor == 1.0_wp, "factor_min holds")
            call check(suite, t(2)%fails .and. t(2)%factor == 2.0_wp, "factor_max fails")
            consistent = .true.
            halves = .true.
            low = 1.0_wp
            high = 2.0_wp
            do k = 1, size(t)
                consistent = consistent .and. (t(k)%fails .eqv. trial_fails(t(k)%displacement, &
                    t(k)%kinetic_ratio, 0.05_wp, 1.0e-3_wp))
                if (k > 2) then
                    halves = halves .and. abs(t(k)%factor - 0.5_wp*(low + high)) < 1.0e-12_wp
                    if (t(k)%fails) then
                        high = t(k)%factor
                    else
                        low = t(k)%factor
                    end if
                end if
                consistent = consistent .and. directory_exists(t(k)%folder)
            end do
            call check(suite, consistent, "every verdict is the criterion's, every trial has its folder")
            call check(suite, halves, "each trial halves the bracket so far")
            call check(suite, outcome%holds == low .and. outcome%fails == high, "the bracket is the last one")
            call check(suite, high - low <= 0.05_wp, "the bracket is within the tolerance")
            call check(suite, outcome%factor_of_safety > 1.3_wp .and. outcome%factor_of_safety < 1.7_wp, &
                "factor of safety between 1.3 and 1.7 (Griffiths and Lane 1.4, coarse grid)")
            print "(a,f0.4,a,f0.4,a,f0.4)", "  factor of safety ", outcome%factor_of_safety, &
                ", holds at ", low, ", fails at ", high
            print "(a,es10.3,a,es10.3)", "  displacement at factor_min ", t(1)%displacement, &
                " m, at factor_max ", t(2)%displacement
            call check(suite, t(1)%displacement < 0.05_wp .and. t(2)%displacement > 1.0_wp, &
                "the slope stands at F = 1 and slides by metres at F = 2")
        end associate
        call check(suite, cohesion(case) == c0 .and. c0 == 4905.0_wp, "the case's strength is unchanged")
        lines = 0
        open (newunit=unit, file=dir//"/strength_reduction.csv", status="old", action="read", &
            iostat=ios)
        call check(suite, ios == 0, "strength_reduction.csv written")
        if (ios == 0) then
            do
                read (unit, "(a)", iostat=ios) line
                if (ios /= 0) exit
                lines = lines + 1
            end do
            close (unit)
        end if
        call check(suite, lines == size(outcome%trials) + 1, "the table has a line per trial")

        ! holds at factor_max: no factor of safety, and the run says where it lies
        call execute_command_line("rm -rf '"//dir//"'")
        call read_case_string(slope_case("1.2", "0.05"), case, error)
        call run_strength_reduction(case, options, outcome, error)
        call check(suite, .not. allocated(error), "analysis up to 1.2 runs")
        if (.not. allocated(error)) then
            call check(suite, size(outcome%trials) == 2 .and. .not. outcome%trials(2)%fails &
                .and. outcome%factor_of_safety == 0.0_wp, "holds at factor_max: no factor")
        end if
        call check(suite, file_exists(dir//"/strength_reduction.csv"), "its table is written")
        call execute_command_line("rm -rf '"//dir//"'")
    end subroutine analysis

end program test_strength_reduction
