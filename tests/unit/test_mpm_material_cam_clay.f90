!> Modified Cam Clay (`materials[i].type = "cam_clay"`): element tests against the closed forms
!> of the critical-state model (Wood 1990, Soil Behaviour and Critical State Soil Mechanics,
!> ch. 6 and 7), in 3D (6 components), axial loading along x.
!>
!> With p the mean effective stress, q the deviator stress, eta = q / p, Lambda = 1 - kappa /
!> lambda and the indices per unit of v0 = 1 + e0 (lambda*, kappa*):
!> - isotropic compression: elastic below pc, p = p0 exp(eps_v / kappa*); on the normal
!>   compression line eps_v = lambda* ln(p / p0) (pc = p);
!> - undrained triaxial compression of a normally consolidated clay: p / p0 = (M^2 / (M^2 +
!>   eta^2))^Lambda all along the path, to the critical state q = M p at p0 2^-Lambda; of an
!>   overconsolidated clay (OCR = 4, dry side): p constant while elastic, first yield at
!>   q = M sqrt(p0 (pc0 - p0)), failure at p_f = p0^(kappa/lambda) (pc0 / 2)^Lambda > p0;
!> - drained triaxial compression (cell pressure held, p = p0 + q / 3) of a normally
!>   consolidated clay: eps_v = lambda* ln(p / p0) + (lambda* - kappa*) ln(1 + eta^2 / M^2)
!>   all along the path, the plastic shear strain against the integral of d eps_q^p =
!>   d eps_v^p 2 eta / (M^2 - eta^2), approaching q = M p at p = 3 p0 / (3 - M).
!> The volumetric law is integrated exactly over a step and the return is implicit, so the
!> relations between p, pc and the volume hold at the end of every step to the Newton
!> tolerance; the plastic shear strain is first order in the step (checked to 1 %).
!> Also: the wave speed grows with p; a stress-free start holds the stiffness of p_min; the
!> case reader refuses kappa >= lambda, OCR < 1, M <= 0 and a missing index.
program test_mpm_material_cam_clay
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_testing_case, only: soil_case, expect_error
    use mpm_material_cam_clay, only: cam_clay_material_type, new_cam_clay_material
    use mpm_stress, only: mean_and_deviator
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: m_csl = 1.2_wp, lambda = 0.2_wp, kappa = 0.04_wp, e0 = 1.0_wp
    real(wp), parameter :: nu = 0.3_wp, p0 = 1.0e5_wp
    real(wp), parameter :: big_lambda = 1.0_wp - kappa/lambda
    real(wp), parameter :: no_spin(3) = 0.0_wp
    real(wp) :: volume_strain
        !! volumetric strain of the drained test, tension positive [-]

    call new_suite(suite, "mpm_material_cam_clay")
    call isotropic_compression()
    call undrained_normally_consolidated()
    call undrained_overconsolidated()
    call drained_normally_consolidated()
    call stiffness_and_start()
    call refused()
    call finish(suite)

contains

    !> p and q of a stress (compression positive p).
    subroutine invariants(stress, p, q)
        real(wp), intent(in) :: stress(:)
        real(wp), intent(out) :: p, q

        real(wp) :: mean, dev(6), radius

        call mean_and_deviator(stress, mean, dev(1:size(stress)), radius)
        p = -mean
        q = sqrt(3.0_wp)*radius
    end subroutine invariants

    !> The clay of the tests, of a given OCR.
    function clay(ocr) result(mat)
        real(wp), intent(in) :: ocr
        type(cam_clay_material_type) :: mat

        call new_cam_clay_material(mat, m_csl, lambda, kappa, e0, nu, 1800.0_wp, ocr, 1.0e3_wp)
    end function clay

    subroutine isotropic_compression()
        type(cam_clay_material_type) :: mat
        real(wp) :: stress(6), state(2), p, q, eps
        integer :: i
        integer, parameter :: nsteps = 200

        ! OCR 4: elastic up to pc = 4 p0; compress by 0.02 (p reaches p0 e^1 < 4 p0)
        mat = clay(4.0_wp)
        stress = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        state = 0.0_wp
        eps = 0.0_wp
        do i = 1, nsteps
            call mat%update_stress(stress, [spread(-1.0e-4_wp/3.0_wp, 1, 3), &
                0.0_wp, 0.0_wp, 0.0_wp], no_spin, 1.0_wp, state)
            eps = eps + 1.0e-4_wp
        end do
        call invariants(stress, p, q)
        call check_close(suite, p/p0, exp(eps/mat%kappa_star()), 1.0e-12_wp, &
            "isotropic, elastic: p = p0 exp(eps_v / kappa*)")
        call check_close(suite, state(2), 4.0_wp*p0, 1.0e-9_wp*p0, "elastic: pc unchanged")
        call check_close(suite, q, 0.0_wp, 1.0e-9_wp*p0, "isotropic: q = 0")
        ! OCR 1: along the normal compression line
        mat = clay(1.0_wp)
        stress = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        state = 0.0_wp
        do i = 1, nsteps
            call mat%update_stress(stress, [spread(-1.0e-4_wp/3.0_wp, 1, 3), &
                0.0_wp, 0.0_wp, 0.0_wp], no_spin, 1.0_wp, state)
        end do
        call invariants(stress, p, q)
        call check_close(suite, p/p0, exp(eps/mat%lambda_star()), 1.0e-9_wp, &
            "isotropic, normally consolidated: p = p0 exp(eps_v / lambda*)")
        call check_close(suite, state(2)/p, 1.0_wp, 1.0e-9_wp, "on the NCL: pc = p")
    end subroutine isotropic_compression

    subroutine undrained_normally_consolidated()
        type(cam_clay_material_type) :: mat
        real(wp) :: stress(6), state(2), de(6), p, q, eta, worst
        integer :: i
        integer, parameter :: nsteps = 4000

        mat = clay(1.0_wp)
        stress = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        state = 0.0_wp
        ! axial compression at constant volume: 0.5 % per 100 steps, 20 % in all
        de = [-5.0e-5_wp, 2.5e-5_wp, 2.5e-5_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        worst = 0.0_wp
        do i = 1, nsteps
            call mat%update_stress(stress, de, no_spin, 1.0_wp, state)
            call invariants(stress, p, q)
            eta = q/p
            worst = max(worst, abs(p/p0 - (m_csl**2/(m_csl**2 + eta**2))**big_lambda))
        end do
        call check_close(suite, worst, 0.0_wp, 1.0e-9_wp, &
            "undrained NC: p / p0 = (M^2 / (M^2 + eta^2))^Lambda along the whole path")
        call check_close(suite, q/p, m_csl, 1.0e-4_wp, "undrained NC: reaches q = M p")
        call check_close(suite, p/p0, 0.5_wp**big_lambda, 1.0e-4_wp, &
            "undrained NC: at the critical state p = p0 2^-Lambda")
        call check_close(suite, state(2)/p, 2.0_wp, 1.0e-4_wp, "critical state: pc = 2 p")
    end subroutine undrained_normally_consolidated

    subroutine undrained_overconsolidated()
        type(cam_clay_material_type) :: mat
        real(wp) :: stress(6), state(2), de(6), p, q, q_prev, q_yield, pf
        integer :: i
        integer, parameter :: nsteps = 4000
        logical :: yielded

        mat = clay(4.0_wp)
        stress = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        state = 0.0_wp
        de = [-5.0e-5_wp, 2.5e-5_wp, 2.5e-5_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        q_yield = m_csl*sqrt(p0*(4.0_wp*p0 - p0))
        yielded = .false.
        q_prev = 0.0_wp
        do i = 1, nsteps
            call mat%update_stress(stress, de, no_spin, 1.0_wp, state)
            call invariants(stress, p, q)
            if (.not. yielded .and. state(1) > 0.0_wp) then
                yielded = .true.
                ! the step that yields goes from inside to beyond the first yield
                call check(suite, q_prev <= q_yield .and. q >= q_yield*(1.0_wp - 1.0e-9_wp), &
                    "undrained OC: first yield at q = M sqrt(p0 (pc0 - p0))")
            end if
            if (.not. yielded) q_prev = q
            if (.not. yielded .and. i == 10) call check_close(suite, p, p0, 1.0e-9_wp*p0, &
                "undrained OC: p constant while elastic")
        end do
        call check(suite, yielded, "undrained OC: yields")
        pf = p0**(kappa/lambda)*(2.0_wp*p0)**big_lambda
        call check_close(suite, p/pf, 1.0_wp, 1.0e-4_wp, &
            "undrained OC: fails at p_f = p0^(kappa/lambda) (pc0 / 2)^Lambda (dilatant, > p0)")
        call check_close(suite, q/p, m_csl, 1.0e-4_wp, "undrained OC: at q = M p")
    end subroutine undrained_overconsolidated

    !> One axial strain step with the radial stress held at -p0: the radial strain increment
    !> found by the secant method.
    subroutine drained_step(mat, stress, state, dea)
        type(cam_clay_material_type), intent(in) :: mat
        real(wp), intent(inout) :: stress(6), state(2)
        real(wp), intent(in) :: dea

        real(wp) :: der(2), f(2), trial(6), trial_state(2), next
        integer :: it

        der = [-0.5_wp*dea, 0.0_wp]
        do it = 1, 2
            trial = stress
            trial_state = state
            call mat%update_stress(trial, [dea, der(it), der(it), 0.0_wp, 0.0_wp, 0.0_wp], &
                no_spin, 1.0_wp, trial_state)
            f(it) = trial(2) + p0
        end do
        do it = 1, 60
            if (abs(f(2)) <= 1.0e-9_wp*p0 .or. f(2) == f(1)) exit
            next = der(2) - f(2)*(der(2) - der(1))/(f(2) - f(1))
            der = [der(2), next]
            trial = stress
            trial_state = state
            call mat%update_stress(trial, [dea, next, next, 0.0_wp, 0.0_wp, 0.0_wp], no_spin, &
                1.0_wp, trial_state)
            f = [f(2), trial(2) + p0]
        end do
        stress = trial
        state = trial_state
        volume_strain = volume_strain + dea + 2.0_wp*der(2)
    end subroutine drained_step

    subroutine drained_normally_consolidated()
        type(cam_clay_material_type) :: mat
        real(wp) :: stress(6), state(2), p, q, eta, eps_v, expected, worst, eps_vp, eps_vp_prev
        real(wp) :: eps_q_ref, eta_prev, worst_q
        integer :: i

        mat = clay(1.0_wp)
        stress = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        state = 0.0_wp
        volume_strain = 0.0_wp
        worst = 0.0_wp
        worst_q = 0.0_wp
        eps_q_ref = 0.0_wp
        eps_vp_prev = 0.0_wp
        eta_prev = 0.0_wp
        do i = 1, 6000
            call drained_step(mat, stress, state, -1.0e-4_wp)
            call invariants(stress, p, q)
            call check_radial(stress)
            eta = q/p
            eps_v = -volume_strain
            expected = mat%lambda_star()*log(p/p0) + (mat%lambda_star() - mat%kappa_star()) &
                *log(1.0_wp + eta**2/m_csl**2)
            worst = max(worst, abs(eps_v - expected))
            ! the plastic shear strain by the trapezoidal rule in the plastic volumetric strain
            eps_vp = (mat%lambda_star() - mat%kappa_star())*log(state(2)/p0)
            if (eta < 0.9_wp*m_csl) then
                eps_q_ref = eps_q_ref + 0.5_wp*(eps_vp - eps_vp_prev) &
                    *(flow_ratio(eta_prev) + flow_ratio(eta))
                if (eta > 0.3_wp*m_csl) worst_q = max(worst_q, abs(state(1)/eps_q_ref - 1.0_wp))
            end if
            eps_vp_prev = eps_vp
            eta_prev = eta
        end do
        call check_close(suite, worst, 0.0_wp, 1.0e-8_wp, "drained NC: eps_v = lambda* ln(p / p0) " &
            //"+ (lambda* - kappa*) ln(1 + eta^2 / M^2) along the whole path")
        call check_close(suite, abs(p - p0 - q/3.0_wp)/p0, 0.0_wp, 1.0e-8_wp, &
            "drained: the path p = p0 + q / 3")
        call check_close(suite, worst_q, 0.0_wp, 1.0e-2_wp, &
            "drained NC: plastic shear strain = integral of 2 eta / (M^2 - eta^2) d eps_v^p " &
            //"(eta from 0.3 M to 0.9 M)")
        call check_close(suite, q/p, m_csl, 1.0e-2_wp, "drained NC: approaches q = M p")
        call check_close(suite, p/(3.0_wp*p0/(3.0_wp - m_csl)), 1.0_wp, 1.0e-2_wp, &
            "drained NC: approaches p = 3 p0 / (3 - M)")
    end subroutine drained_normally_consolidated

    !> 2 eta / (M^2 - eta^2).
    pure real(wp) function flow_ratio(eta)
        real(wp), intent(in) :: eta
        flow_ratio = 2.0_wp*eta/(m_csl**2 - eta**2)
    end function flow_ratio

    !> The radial stresses held at the cell pressure.
    subroutine check_radial(stress)
        real(wp), intent(in) :: stress(6)
        if (abs(stress(2) + p0) > 1.0e-6_wp*p0 .or. abs(stress(3) + p0) > 1.0e-6_wp*p0) &
            call check(suite, .false., "drained: radial stress held at the cell pressure")
    end subroutine check_radial

    subroutine stiffness_and_start()
        type(cam_clay_material_type) :: mat
        real(wp) :: stress(6), state(2)

        mat = clay(1.0_wp)
        call check(suite, mat%speed_varies(), "the wave speed follows the stress")
        call check(suite, mat%wave_speed_at([-4.0e5_wp, -4.0e5_wp, -4.0e5_wp, 0.0_wp, 0.0_wp, &
            0.0_wp], state) > 1.9_wp*mat%wave_speed_at([-1.0e5_wp, -1.0e5_wp, -1.0e5_wp, &
            0.0_wp, 0.0_wp, 0.0_wp], state), "c_p grows as sqrt(p): doubles from p0 to 4 p0")
        call check_close(suite, mat%wave_speed(), mat%wave_speed_at(spread(0.0_wp, 1, 6), &
            state), 1.0e-12_wp*mat%wave_speed(), "wave_speed() is the speed at p_min")
        ! stress-free start: pc = OCR p_min, the stiffness of p_min
        stress = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(stress, [-1.0e-6_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
            no_spin, 1.0_wp, state)
        call check_close(suite, state(2), 1.0e3_wp, 1.0e-6_wp, "stress-free start: pc = p_min")
        call check(suite, all(stress(1:3) < 0.0_wp), "stress-free start: compression gives " &
            //"compression (stiffness of p_min)")
        call check_close(suite, mat%at_rest_ratio(), 1.0_wp - 3.0_wp*m_csl/(6.0_wp + m_csl), &
            1.0e-15_wp, "K0 = 1 - sin(phi_cs), sin(phi_cs) = 3 M / (6 + M)")
    end subroutine stiffness_and_start

    subroutine refused()
        character(len=*), parameter :: base = '"type": "cam_clay", "M": 1.2, "e0": 1.0, ' &
            //'"nu": 0.3, "rho": 1800'

        call expect_error(suite, soil_case(base//', "lambda": 0.2, "kappa": 0.2'), &
            [character(len=200) :: "materials[1].kappa = 0.2 is not below materials[1].lambda"], &
            "kappa not below lambda")
        call expect_error(suite, soil_case(base//', "lambda": 0.2'), [character(len=200) :: &
            "missing required key 'materials[1].kappa'"], "kappa missing")
        call expect_error(suite, soil_case(base//', "lambda": 0.2, "kappa": 0.04, "OCR": 0.5'), &
            [character(len=200) :: "materials[1].OCR = 0.5 is out of range: must be >= 1"], &
            "OCR below 1")
        call expect_error(suite, soil_case('"type": "cam_clay", "M": 0, "lambda": 0.2, ' &
            //'"kappa": 0.04, "e0": 1, "nu": 0.3, "rho": 1800'), [character(len=200) :: &
            "materials[1].M = 0 is out of range"], "M zero")
    end subroutine refused

end program test_mpm_material_cam_clay
