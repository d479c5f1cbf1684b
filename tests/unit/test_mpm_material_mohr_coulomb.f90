!> Mohr-Coulomb material: element tests against closed forms (triaxial compression at constant
!> cell pressure and at constant mean stress, simple shear), the flow rule on a face and on the
!> compression meridian, the exact return to every region of the surface (face, both edges,
!> apex, cut-off face, its edges and corners; 2D and 3D), isotropic compression, objectivity,
!> degenerate parameters and softening; the closed-form 3D eigen-decomposition against the
!> Jacobi one for nearly repeated principal stresses.
!>
!> Mixed stress/strain control (a confining stress held while an axial or shear strain is
!> driven) is solved per step by the secant method on the free strain increment to a residual
!> of tol_mixed = 1e3 eps p0 (the stress itself carries a round-off of a few eps p0).
!> Tolerances for strengths add that residual, scaled by the slope of the yield surface, to the
!> round-off of the return, 100 eps times the stress scale.
program test_mpm_material_mohr_coulomb
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use mpm_kinds, only: wp, i8
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_softening, only: softening_none, softening_linear, softening_exponential
    use mpm_strength, only: strength_type
    use mpm_material_mohr_coulomb, only: mohr_coulomb_material_type, new_mohr_coulomb_material, &
        mohr_coulomb_principal_return, mohr_coulomb_return_chunk_3d
    use mpm_material, only: material_chunk
    use mpm_stress, only: double_contraction
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: pi = acos(-1.0_wp), deg = pi/180.0_wp
    real(wp), parameter :: young = 1.0e7_wp, poisson = 0.3_wp
    real(wp), parameter :: shear = young/(2.0_wp*(1.0_wp + poisson))
    real(wp), parameter :: lame = young*poisson/((1.0_wp + poisson)*(1.0_wp - 2.0_wp*poisson))
    real(wp), parameter :: bulk = lame + 2.0_wp*shear/3.0_wp
    real(wp), parameter :: p0 = 1.0e5_wp      ! confining pressure [Pa]
    real(wp), parameter :: eps = epsilon(1.0_wp)
    real(wp), parameter :: tol_mixed = 1.0e3_wp*eps*p0
    real(wp), parameter :: zero3(3) = 0.0_wp
    integer, parameter :: constant_cell = 1, constant_mean = 2
    ! the materials of the chunk tests: with an apex (phi > 0, with and without cohesion,
    ! associated and not) and without (Tresca)
    real(wp), parameter :: chunk_phis(4) = [30.0_wp, 40.0_wp, 0.0_wp, 25.0_wp]
    real(wp), parameter :: chunk_cohs(4) = [0.0_wp, 1.0e4_wp, 2.0e4_wp, 5.0e3_wp]
    real(wp), parameter :: chunk_psis(4) = [0.0_wp, 10.0_wp, 0.0_wp, 25.0_wp]

    call new_suite(suite, "mpm_material_mohr_coulomb")
    call check_triaxial(30.0_wp, 0.0_wp, 0.0_wp)
    call check_triaxial(30.0_wp, 1.0e4_wp, 0.0_wp)
    call check_triaxial(0.0_wp, 2.0e4_wp, 0.0_wp)
    call check_triaxial(30.0_wp, 1.0e4_wp, 10.0_wp)
    call check_simple_shear(30.0_wp, 30.0_wp, 0.0_wp)
    call check_simple_shear(30.0_wp, 0.0_wp, 5.0e3_wp)
    call check_simple_shear(35.0_wp, 10.0_wp, 0.0_wp)
    call check_isotropic_compression()
    call check_face_dilatancy()
    call check_returns()
    call check_random_returns()
    call check_block_update()
    call check_chunk_return()
    call check_chunk_return_3d()
    call check_close_eigenvalues()
    call check_rigid_rotation_2d()
    call check_rigid_rotation_3d()
    call check_degenerate()
    call check_softening(softening_linear)
    call check_softening(softening_exponential)
    call finish(suite)

contains

    !> A material with E = 10 MPa, nu = 0.3 and the given strength (angles in degrees).
    subroutine make_material(mat, phi, coh, psi, tcut, softening, phi_r, coh_r, psi_r, strain)
        type(mohr_coulomb_material_type), intent(out) :: mat
        real(wp), intent(in) :: phi, coh, psi, tcut
        integer, intent(in), optional :: softening
        real(wp), intent(in), optional :: phi_r, coh_r, psi_r, strain
        type(strength_type) :: spec

        spec%friction = phi*deg
        spec%cohesion = coh
        spec%dilatancy = psi*deg
        spec%tension_cutoff = tcut
        spec%softening = softening_none
        if (present(softening)) then
            spec%softening = softening
            spec%friction_residual = phi_r*deg
            spec%cohesion_residual = coh_r
            spec%dilatancy_residual = psi_r*deg
            spec%softening_strain = strain
        end if
        call new_mohr_coulomb_material(mat, young, poisson, 2000.0_wp, spec)
    end subroutine make_material

    !> Mohr-Coulomb f of principal stresses in any order [Pa] (phi in radians).
    pure real(wp) function yield_mc(p, phi, coh)
        real(wp), intent(in) :: p(3), phi, coh
        yield_mc = (maxval(p) - minval(p)) + (maxval(p) + minval(p))*sin(phi) - 2*coh*cos(phi)
    end function yield_mc

    !> Elastic strain of a stress increment (Voigt, tensor components), Hooke's law inverted.
    pure function compliance(sig) result(e)
        real(wp), intent(in) :: sig(:)
        real(wp) :: e(size(sig))
        e = (1 + poisson)/young*sig
        e(1:3) = e(1:3) - poisson/young*(sig(1) + sig(2) + sig(3))
    end function compliance

    !> Normal strains C^-1 sigma of normal stresses (no shear).
    pure function compliance_normal(s) result(e)
        real(wp), intent(in) :: s(:)
        real(wp) :: e(3)
        e = ((1.0_wp + poisson)*s(1:3) - poisson*sum(s(1:3)))/young
    end function compliance_normal

    !> One step of a mixed test: the strain increment `de` with its component `free` (and
    !> `free2`, when given, set equal) chosen so that `control` holds after the update:
    !> `constant_cell`: stress(free) = target; `constant_mean`: mean stress = target.
    !> Secant iteration from the elastic estimate; `slope` is the elastic d(control)/d(free).
    subroutine mixed_step(mat, stress, state, de, free, free2, control, target, slope, ok)
        type(mohr_coulomb_material_type), intent(in) :: mat
        real(wp), intent(inout) :: stress(:), state(:), de(:)
        integer, intent(in) :: free, free2, control
        real(wp), intent(in) :: target, slope
        logical, intent(out) :: ok
        real(wp) :: x0, x1, r0, r1, x2, s(size(stress)), st(size(state))
        integer :: it

        x0 = 0.0_wp
        call mixed_eval(mat, stress, state, de, free, free2, control, target, x0, s, st, r0)
        x1 = x0 - r0/slope
        ok = .false.
        do it = 1, 60
            call mixed_eval(mat, stress, state, de, free, free2, control, target, x1, s, st, r1)
            if (abs(r1) <= tol_mixed) then
                ok = .true.
                exit
            end if
            if (it == 60) exit
            if (r1 == r0) then
                x2 = x1 - r1/slope
            else
                x2 = x1 - r1*(x1 - x0)/(r1 - r0)
            end if
            x0 = x1
            r0 = r1
            x1 = x2
        end do
        stress = s
        state = st
    end subroutine mixed_step

    !> Update a copy of (stress, state) with the free strain component(s) set to x; return
    !> the updated copy and the residual of the control condition.
    subroutine mixed_eval(mat, stress, state, de, free, free2, control, target, x, s, st, res)
        type(mohr_coulomb_material_type), intent(in) :: mat
        real(wp), intent(in) :: stress(:), state(:), target, x
        real(wp), intent(inout) :: de(:)
        integer, intent(in) :: free, free2, control
        real(wp), intent(out) :: s(:), st(:), res

        de(free) = x
        if (free2 > 0) de(free2) = x
        s = stress
        st = state
        call mat%update_stress(s, de, zero3, 1.0_wp, st)
        if (control == constant_cell) then
            res = s(free) - target
        else
            res = (s(1) + s(2) + s(3))/3 - target
        end if
    end subroutine mixed_eval

    !> Triaxial compression (3D, axial z, lateral x = y) from the isotropic stress -p0.
    !> - at constant cell pressure (sigma_xx = sigma_yy = -p0): with s1 = s2 = -p0 and
    !>   s3 = -p0 - q on the compression edge, f = 0 gives q = 2 (c cos(phi) + p0 sin(phi)) /
    !>   (1 - sin(phi)); this is REFERENCES section 6, q = 6 (c cos(phi) + p sin(phi)) /
    !>   (3 - sin(phi)), with p = p0 + q/3 the mean pressure at failure;
    !> - at constant mean pressure p = p0, the same formula with p = p0 directly.
    !> After the peak the strength stays (perfect plasticity): q at the end equals the peak.
    !> Flow rule on the compression edge, d eps^p = dl (b_A + b_C) with equal multipliers by
    !> symmetry: d eps_v^p / (-d eps_a^p) = 2 sin(psi) / (1 - sin(psi)) (REFERENCES section 6).
    !> Tolerances: q to tol_mixed times the slope dq/dsigma_r <= (1 + sin phi)/(1 - sin phi) <= 3
    !> plus the round-off of the return, 100 eps (p0 + q); the ratio of strain increments is
    !> computed from increments of 2e-4 with errors of about (tol_mixed + 100 eps p0) / G
    !> each: tol_ratio = 10 (tol_mixed + 100 eps p0) / (G |d eps_a|), about 3e-10.
    !> Plastic work at constant cell pressure: the work of the stresses (trapezoidal) minus the
    !> change of the stored elastic energy 1/2 sigma : C^-1 : sigma (elastic_energy_block) is,
    !> for a sharp yield at eps_a = q / E and perfect flow after it,
    !> W_p = (q + r sigma_1)(|eps_a| - q / E), r = 2 sin(psi) / (1 - sin(psi)) (the work
    !> sigma : d eps^p of the steady flow); within q |d eps_a| (the step that crosses the yield
    !> point is partly elastic) plus the elastic energy at the strength, q^2 / E, times tol_ratio.
    subroutine check_triaxial(phi_deg, coh, psi_deg)
        real(wp), intent(in) :: phi_deg, coh, psi_deg
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: stress(6), state(2), de(6), phi, psi, q, qf, qmax, tol_q, sold(6), vold
        real(wp) :: dep(6), ratio, ratio_expected, tol_ratio, work, density(1), stored0, wp_exact
        integer :: mode, k
        integer, parameter :: nsteps = 300
        real(wp), parameter :: dea = -2.0e-4_wp
        logical :: ok, all_ok
        character(len=80) :: label

        call make_material(mat, phi_deg, coh, psi_deg, -1.0_wp)
        phi = phi_deg*deg
        psi = psi_deg*deg
        tol_ratio = 10*(tol_mixed + 100*eps*p0)/(shear*abs(dea))
        do mode = constant_cell, constant_mean
            write (label, "(a,f4.1,a,es8.1,a,f4.1,a)") "triaxial phi ", phi_deg, " c ", coh, &
                " psi ", psi_deg, merge(" cell", " mean", mode == constant_cell)
            if (mode == constant_cell) then
                qf = 2*(coh*cos(phi) + p0*sin(phi))/(1 - sin(phi))
            else
                qf = 6*(coh*cos(phi) + p0*sin(phi))/(3 - sin(phi))
            end if
            stress = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
            state = 0.0_wp
            qmax = 0.0_wp
            all_ok = .true.
            ratio = 0.0_wp
            work = 0.0_wp
            call mat%elastic_energy_block(1, reshape(stress, [6, 1]), reshape(state, [2, 1]), &
                density)
            stored0 = density(1)
            do k = 1, nsteps
                de = [0.0_wp, 0.0_wp, dea, 0.0_wp, 0.0_wp, 0.0_wp]
                sold = stress
                vold = state(2)
                if (mode == constant_cell) then
                    call mixed_step(mat, stress, state, de, 1, 2, constant_cell, -p0, &
                        2*(shear + lame), ok)
                else
                    call mixed_step(mat, stress, state, de, 1, 2, constant_mean, -p0, &
                        2*bulk, ok)
                end if
                all_ok = all_ok .and. ok
                work = work + 0.5_wp*double_contraction(sold + stress, de)
                qmax = max(qmax, stress(1) - stress(3))
                dep = de - compliance(stress - sold)
                if (k == nsteps) ratio = (dep(1) + dep(2) + dep(3))/(-dep(3))
            end do
            q = stress(1) - stress(3)
            tol_q = 3*tol_mixed + 100*eps*(p0 + qf)
            call check(suite, all_ok, trim(label)//": mixed control converged")
            call check_close(suite, q, qf, tol_q, trim(label)//": strength q")
            call check(suite, qmax <= qf + tol_q, trim(label)//": q never above the strength")
            call check(suite, state(1) > 0.0_wp, trim(label)//": plastic shear strain")
            call check_close(suite, stress(1), stress(2), 100*eps*p0, &
                trim(label)//": lateral stresses stay equal")
            ratio_expected = 2*sin(psi)/(1 - sin(psi))
            call check_close(suite, ratio, ratio_expected, tol_ratio, &
                trim(label)//": dilatancy d eps_v^p / -d eps_a^p")
            call check_close(suite, state(2) - vold, dep(1) + dep(2) + dep(3), &
                tol_ratio*abs(dea), trim(label)//": state(2) is the plastic volumetric strain")
            if (mode == constant_cell) then
                call mat%elastic_energy_block(1, reshape(stress, [6, 1]), &
                    reshape(state, [2, 1]), density)
                wp_exact = (qf + ratio_expected*stress(1))*(nsteps*abs(dea) - qf/young)
                call check_close(suite, work - (density(1) - stored0), wp_exact, &
                    qf*abs(dea) + tol_ratio*qf**2/young, trim(label)// &
                    ": plastic work = work - stored elastic energy")
                call check_close(suite, density(1) - stored0, &
                    0.5_wp*(dot_product(stress(1:3), compliance_normal(stress)) &
                    - dot_product([-p0, -p0, -p0], compliance_normal([-p0, -p0, -p0]))), &
                    100*eps*qf**2/young, trim(label)//": stored energy 1/2 sigma : C^-1 : sigma")
            end if
        end do
    end subroutine check_triaxial

    !> Plane-strain simple shear with the normal stress sigma_yy = -sigma_n held (eps_xx = 0,
    !> eps_zz = 0), from the isotropic stress -sigma_n. At steady plastic flow the stress no
    !> longer changes, so the whole strain rate is plastic: d eps_xx^p = 0 and d eps_zz^p = 0
    !> (s_zz intermediate, face return). The plastic strain rate has principal values
    !> dl (1 + sin psi) and -dl (1 - sin psi), centre dl sin psi and radius dl, so the x
    !> direction (no extension) makes cos(2 a) = -sin(psi) with the major direction; the
    !> stress is coaxial, so with the Mohr circle centre m and radius t:
    !> sigma_yy = m + t sin(psi), tau_xy = t cos(psi). With t = c cos(phi) - m sin(phi):
    !>   tau = cos(psi) (c cos(phi) + sigma_n sin(phi)) / (1 - sin(phi) sin(psi))
    !> (Davis 1968); psi = phi gives the classic tau = c + sigma_n tan(phi), psi = 0 gives
    !> tau = c cos(phi) + sigma_n sin(phi). The Mohr circle touches the envelope at every
    !> plastic step: t = c cos(phi) - m sin(phi) with s1, s3 the extreme principal stresses.
    !> The stepwise update reaches that state exactly after a finite shear strain (a fixed
    !> point of the exact return: sigma repeats, so the whole increment is plastic, coaxial
    !> with sigma, as in the continuum argument). After gamma = 1, about 80 times the elastic
    !> limit, tau must not change over the last 10 % of the loading (to 100 eps tau) and
    !> must equal the closed form to tol_mixed (d tau / d sigma_n <= 1) plus 100 eps
    !> (sigma_n + tau).
    subroutine check_simple_shear(phi_deg, psi_deg, coh)
        real(wp), intent(in) :: phi_deg, psi_deg, coh
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: stress(4), state(2), de(4), phi, psi, tau, tau_f, m, t, centre, radius
        real(wp) :: tau_90, fmax
        integer :: k
        integer, parameter :: nsteps = 2000
        real(wp), parameter :: dgamma = 5.0e-4_wp, sn = p0
        logical :: ok, all_ok
        character(len=80) :: label

        call make_material(mat, phi_deg, coh, psi_deg, -1.0_wp)
        phi = phi_deg*deg
        psi = psi_deg*deg
        write (label, "(a,f4.1,a,f4.1,a,es8.1)") "simple shear phi ", phi_deg, " psi ", &
            psi_deg, " c ", coh
        stress = [-sn, -sn, -sn, 0.0_wp]
        state = 0.0_wp
        all_ok = .true.
        fmax = 0.0_wp
        tau_90 = 0.0_wp
        do k = 1, nsteps
            de = [0.0_wp, 0.0_wp, 0.0_wp, 0.5_wp*dgamma]
            call mixed_step(mat, stress, state, de, 2, 0, constant_cell, -sn, lame + 2*shear, ok)
            all_ok = all_ok .and. ok
            centre = 0.5_wp*(stress(1) + stress(2))
            radius = hypot(0.5_wp*(stress(1) - stress(2)), stress(4))
            if (state(1) > 0.0_wp) fmax = max(fmax, abs(yield_mc([centre + radius, &
                centre - radius, stress(3)], phi, coh)))
            if (k == 9*nsteps/10) tau_90 = stress(4)
        end do
        tau = stress(4)
        tau_f = cos(psi)*(coh*cos(phi) + sn*sin(phi))/(1 - sin(phi)*sin(psi))
        m = 0.5_wp*(stress(1) + stress(2))
        t = hypot(0.5_wp*(stress(1) - stress(2)), stress(4))
        call check(suite, all_ok, trim(label)//": mixed control converged")
        call check(suite, stress(3) < m + t .and. stress(3) > m - t, &
            trim(label)//": s_zz is the intermediate principal stress")
        call check(suite, fmax <= 100*eps*(sn + tau_f), &
            trim(label)//": the Mohr circle touches the envelope at every plastic step")
        call check_close(suite, t, coh*cos(phi) - m*sin(phi), 100*eps*(sn + tau_f), &
            trim(label)//": t = c cos(phi) - m sin(phi)")
        call check(suite, abs(tau - tau_90) <= 100*eps*tau_f, &
            trim(label)//": steady state reached")
        call check_close(suite, tau, tau_f, tol_mixed + 100*eps*(sn + tau_f), &
            trim(label)//": steady tau_xy")
        call check_close(suite, stress(2), m + t*sin(psi), tol_mixed + 100*eps*(sn + tau_f), &
            trim(label)//": sigma_yy = m + t sin(psi)")
    end subroutine check_simple_shear

    !> Isotropic compression stays elastic for any friction and cohesion: p = -K eps_v, no
    !> plastic strain (3D, and 2D with the out-of-plane strain increment). Tol: round-off of
    !> Hooke's law over 50 increments, 100 eps K |eps_v|.
    subroutine check_isotropic_compression()
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: s6(6), s4(4), state(2), ev
        integer :: k
        real(wp), parameter :: e = -1.0e-4_wp

        call make_material(mat, 30.0_wp, 0.0_wp, 10.0_wp, 0.0_wp)
        s6 = 0.0_wp
        state = 0.0_wp
        do k = 1, 50
            call mat%update_stress(s6, [e, e, e, 0.0_wp, 0.0_wp, 0.0_wp], zero3, 1.0_wp, state)
        end do
        ev = 50*3*e
        call check_close(suite, sum(s6(1:3))/3, bulk*ev, 100*eps*bulk*abs(ev), &
            "3D isotropic compression: mean stress = K eps_v")
        call check(suite, all(s6(4:6) == 0.0_wp) .and. s6(1) == s6(2) .and. s6(2) == s6(3), &
            "3D isotropic compression stays isotropic")
        call check(suite, all(state == 0.0_wp), "3D isotropic compression: no plastic strain")
        s4 = 0.0_wp
        state = 0.0_wp
        do k = 1, 50
            call mat%update_stress(s4, [e, e, e, 0.0_wp], zero3, 1.0_wp, state)
        end do
        call check_close(suite, sum(s4(1:3))/3, bulk*ev, 100*eps*bulk*abs(ev), &
            "2D isotropic compression: mean stress = K eps_v")
        call check(suite, all(state == 0.0_wp), "2D isotropic compression: no plastic strain")
    end subroutine check_isotropic_compression

    !> Return to the face A (s1 > s2 > s3, 3D, principal axes on x y z): with
    !> g = (s1 - s3) + (s1 + s3) sin(psi), d eps^p = dl (1 + sin psi, 0, -(1 - sin psi)), so
    !> d eps_2^p = 0 and d eps_v^p / (d eps_1^p - d eps_3^p) = sin(psi). The plastic strain is
    !> D^-1 (sigma_trial - sigma), the trial from Hooke's law here. The state holds
    !> eps_q = sqrt(2/3 dev:dev) and eps_v. Tol: round-off of the stresses, 100 eps |sigma|,
    !> divided by G, against plastic strains of about 1e-3.
    subroutine check_face_dilatancy()
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: stress(6), trial(6), state(2), de(6), dep(6), dev(3), tol_e
        real(wp), parameter :: psi = 10.0_wp*deg

        call make_material(mat, 30.0_wp, 0.0_wp, 10.0_wp, -1.0_wp)
        stress = [-1.5e5_wp, -2.0e5_wp, -3.0e5_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        de = [1.0e-2_wp, 0.0_wp, -1.0e-2_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        trial = stress + 2*shear*de
        trial(1:3) = trial(1:3) + lame*sum(de(1:3))
        state = 0.0_wp
        call mat%update_stress(stress, de, zero3, 1.0_wp, state)
        dep = compliance(trial - stress)
        tol_e = 100*eps*4.0e5_wp/shear
        call check(suite, stress(1) > stress(2) .and. stress(2) > stress(3), &
            "face return keeps s1 > s2 > s3")
        call check_close(suite, yield_mc(stress(1:3), 30*deg, 0.0_wp), 0.0_wp, &
            100*eps*4.0e5_wp, "face return: f = 0")
        call check(suite, dep(1) - dep(3) > 1.0e-4_wp, "face return is plastic")
        call check_close(suite, dep(2), 0.0_wp, tol_e, "face return: d eps_2^p = 0")
        call check_close(suite, sum(dep(1:3)), sin(psi)*(dep(1) - dep(3)), tol_e, &
            "face return: d eps_v^p = sin(psi) (d eps_1^p - d eps_3^p)")
        call check_close(suite, state(2), sum(dep(1:3)), tol_e, "face return: state(2)")
        dev = dep(1:3) - sum(dep(1:3))/3
        call check_close(suite, state(1), sqrt(2.0_wp/3.0_wp*sum(dev**2)), tol_e, &
            "face return: state(1) = sqrt(2/3 de:de)")
    end subroutine check_face_dilatancy

    !> 3x3 rotation from three angles (z, x, z).
    pure function rotation(a, b, c) result(r)
        real(wp), intent(in) :: a, b, c
        real(wp) :: r(3, 3), rz1(3, 3), rx(3, 3), rz2(3, 3)
        rz1 = reshape([cos(a), sin(a), 0.0_wp, -sin(a), cos(a), 0.0_wp, 0.0_wp, 0.0_wp, &
            1.0_wp], [3, 3])
        rx = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, cos(b), sin(b), 0.0_wp, -sin(b), &
            cos(b)], [3, 3])
        rz2 = reshape([cos(c), sin(c), 0.0_wp, -sin(c), cos(c), 0.0_wp, 0.0_wp, 0.0_wp, &
            1.0_wp], [3, 3])
        r = matmul(rz1, matmul(rx, rz2))
    end function rotation

    pure function voigt_to_matrix(s) result(m)
        real(wp), intent(in) :: s(6)
        real(wp) :: m(3, 3)
        m = reshape([s(1), s(4), s(6), s(4), s(2), s(5), s(6), s(5), s(3)], [3, 3])
    end function voigt_to_matrix

    pure function matrix_to_voigt(m) result(s)
        real(wp), intent(in) :: m(3, 3)
        real(wp) :: s(6)
        s = [m(1, 1), m(2, 2), m(3, 3), m(1, 2), m(2, 3), m(3, 1)]
    end function matrix_to_voigt

    !> Drive one update from zero stress to the trial with principal values pt along the
    !> columns of r (3D), or, in 2D, with pt(iz) on z and the others in the plane turned by
    !> angle theta. Returns the principal values of the result along the same directions, the
    !> largest off-diagonal entry in that frame (coaxiality) and the state.
    subroutine drive(mat, pt, ndim, r, theta, iz, p, offdiag, state)
        type(mohr_coulomb_material_type), intent(in) :: mat
        real(wp), intent(in) :: pt(3), r(3, 3), theta
        integer, intent(in) :: ndim, iz
        real(wp), intent(out) :: p(3), offdiag, state(2)
        real(wp) :: s6(6), s4(4), m(3, 3), d(3, 3), c, s, a, b
        integer :: ia, ib, i

        state = 0.0_wp
        if (ndim == 3) then
            d = 0.0_wp
            do i = 1, 3
                d(i, i) = pt(i)
            end do
            s6 = 0.0_wp
            call mat%update_stress(s6, compliance(matrix_to_voigt(matmul(r, &
                matmul(d, transpose(r))))), zero3, 1.0_wp, state)
            m = matmul(transpose(r), matmul(voigt_to_matrix(s6), r))
            p = [m(1, 1), m(2, 2), m(3, 3)]
            offdiag = max(abs(m(1, 2)), abs(m(2, 3)), abs(m(1, 3)))
        else
            ia = merge(2, 1, iz == 1)
            ib = 6 - iz - ia
            c = cos(theta)
            s = sin(theta)
            a = pt(ia)
            b = pt(ib)
            s4 = 0.0_wp
            call mat%update_stress(s4, compliance([a*c*c + b*s*s, a*s*s + b*c*c, pt(iz), &
                (a - b)*c*s]), zero3, 1.0_wp, state)
            p(ia) = c*c*s4(1) + s*s*s4(2) + 2*c*s*s4(4)
            p(ib) = s*s*s4(1) + c*c*s4(2) - 2*c*s*s4(4)
            p(iz) = s4(3)
            offdiag = abs((s4(2) - s4(1))*c*s + (c*c - s*s)*s4(4))
        end if
    end subroutine drive

    !> Exact returns to every region, built backwards: a final stress sf on a face, edge or
    !> corner, and a plastic strain ep in the cone of the flow directions of the planes active
    !> there (b_A = (1 + sin psi, 0, -(1 - sin psi)), b_B and b_C its mirrors, e_i on the
    !> cut-off), give the trial sf + D ep. The return of that trial is unique (the matrices of
    !> the active sets have positive principal minors), so the update must give sf and
    !> state = (sqrt(2/3 dev ep : dev ep), tr ep). Done in 3D with rotated principal axes and
    !> in 2D with each principal value in turn out of plane. phi = 30, psi = 10 deg,
    !> c = 10 kPa, sigma_t = 5 kPa (apex c cot(phi) = 17.3 kPa). Tol: 100 eps times the stress
    !> scale for stresses and f; that over G for the state.
    subroutine check_returns()
        type(mohr_coulomb_material_type) :: mcut, mnocut
        real(wp), parameter :: phi = 30.0_wp*deg, psi = 10.0_wp*deg, coh = 1.0e4_wp
        real(wp), parameter :: tcut = 5.0e3_wp
        real(wp) :: sp, sf, k, s3t, apex, ba(3), bb(3), bc(3), e1(3), e2(3), e3(3), s1a, s1b

        call make_material(mcut, 30.0_wp, coh, 10.0_wp, tcut)
        call make_material(mnocut, 30.0_wp, coh, 10.0_wp, -1.0_wp)
        sf = sin(phi)
        sp = sin(psi)
        k = 2*coh*cos(phi)
        ba = [1 + sp, 0.0_wp, -(1 - sp)]
        bb = [1 + sp, -(1 - sp), 0.0_wp]
        bc = [0.0_wp, 1 + sp, -(1 - sp)]
        e1 = [1.0_wp, 0.0_wp, 0.0_wp]
        e2 = [0.0_wp, 1.0_wp, 0.0_wp]
        e3 = [0.0_wp, 0.0_wp, 1.0_wp]
        ! s3 where the pyramid meets the cut-off s1 = sigma_t
        s3t = (tcut*(1 + sf) - k)/(1 - sf)
        apex = coh*cos(phi)/sf
        ! s1 on the face A for s3 = -60 and -50 kPa
        s1a = (k - 6.0e4_wp*(1 - sf))/(1 + sf)
        s1b = (k - 5.0e4_wp*(1 - sf))/(1 + sf)

        call one_return(mcut, "face", [s1a, -3.4e4_wp, -6.0e4_wp], 1.0e-3_wp*ba, phi, coh, &
            tcut, .true.)
        call one_return(mnocut, "face (no cut-off)", [s1a, -3.4e4_wp, -6.0e4_wp], &
            1.0e-3_wp*ba, phi, coh, tcut, .false.)
        call one_return(mcut, "extension edge", [s1b, -5.0e4_wp, -5.0e4_wp], &
            1.0e-3_wp*ba + 2.0e-3_wp*bb, phi, coh, tcut, .true.)
        call one_return(mnocut, "extension edge (no cut-off)", [s1b, -5.0e4_wp, -5.0e4_wp], &
            1.0e-3_wp*ba + 2.0e-3_wp*bb, phi, coh, tcut, .false.)
        call one_return(mcut, "compression edge", [s1b, s1b, -5.0e4_wp], &
            1.5e-3_wp*ba + 0.5e-3_wp*bc, phi, coh, tcut, .true.)
        call one_return(mnocut, "compression edge (no cut-off)", [s1b, s1b, -5.0e4_wp], &
            0.5e-3_wp*ba + 1.5e-3_wp*bc, phi, coh, tcut, .false.)
        ! apex: hydrostatic tension with a small deviator, inside the cone of the b's
        call one_return(mnocut, "apex", [apex, apex, apex], &
            [2.6e-3_wp, 2.0e-3_wp, 1.4e-3_wp], phi, coh, tcut, .false.)
        call one_return(mcut, "cut-off face", [tcut, -2.0e3_wp, -1.0e4_wp], 1.0e-3_wp*e1, &
            phi, coh, tcut, .true.)
        call one_return(mcut, "pyramid meets cut-off", [tcut, -8.0e3_wp, s3t], &
            1.0e-3_wp*ba + 1.0e-3_wp*e1, phi, coh, tcut, .true.)
        call one_return(mcut, "cut-off edge s1 = s2 = sigma_t", [tcut, tcut, -5.0e3_wp], &
            1.0e-3_wp*e1 + 2.0e-3_wp*e2, phi, coh, tcut, .true.)
        call one_return(mcut, "corner (sigma_t, s, s)", [tcut, s3t, s3t], &
            1.0e-3_wp*ba + 1.0e-3_wp*bb + 1.0e-3_wp*e1, phi, coh, tcut, .true.)
        call one_return(mcut, "corner (sigma_t, sigma_t, s)", [tcut, tcut, s3t], &
            1.0e-3_wp*ba + 2.0e-3_wp*bc + 0.5e-3_wp*e1 + 1.0e-3_wp*e2, phi, coh, tcut, .true.)
        call one_return(mcut, "corner (sigma_t, sigma_t, sigma_t)", [tcut, tcut, tcut], &
            1.0e-3_wp*e1 + 2.0e-3_wp*e2 + 0.5e-3_wp*e3, phi, coh, tcut, .true.)
    end subroutine check_returns

    !> One case of `check_returns`: the trial sfinal + D ep must return to sfinal.
    subroutine one_return(mat, what, sfinal, ep, phi, coh, tcut, cut)
        type(mohr_coulomb_material_type), intent(in) :: mat
        character(len=*), intent(in) :: what
        real(wp), intent(in) :: sfinal(3), ep(3), phi, coh, tcut
        logical, intent(in) :: cut
        real(wp) :: pt(3), p(3), off, state(2), scale, dev(3), fsurf, r(3, 3)
        integer :: ndim, iz
        character(len=120) :: label

        pt = sfinal + 2*shear*ep + lame*sum(ep)
        scale = maxval(abs(pt))
        dev = ep - sum(ep)/3
        r = rotation(0.3_wp, 1.1_wp, -0.7_wp)
        do ndim = 2, 3
            do iz = 1, merge(3, 1, ndim == 2)
                write (label, "(a,i0,a,i0,a)") what//" (", ndim, "D, principal ", iz, &
                    " out of plane)"
                if (ndim == 3) label = what//" (3D)"
                call drive(mat, pt, ndim, r, 0.4_wp, iz, p, off, state)
                call check(suite, maxval(abs(p - sfinal)) <= 100*eps*scale, &
                    trim(label)//": returned stress")
                call check(suite, off <= 100*eps*scale, trim(label)//": coaxial")
                fsurf = yield_mc(p, phi, coh)
                if (cut) fsurf = max(fsurf, maxval(p) - tcut)
                call check(suite, abs(fsurf) <= 100*eps*scale, &
                    trim(label)//": on the surface")
                call check(suite, abs(state(2) - sum(ep)) <= 100*eps*scale/shear, &
                    trim(label)//": plastic volumetric strain")
                call check(suite, abs(state(1) - sqrt(2.0_wp/3.0_wp*sum(dev**2))) <= &
                    100*eps*scale/shear, trim(label)//": plastic shear strain")
            end do
        end do
    end subroutine one_return

    !> Random trial stresses (fixed linear congruential sequence) for several materials, in 3D
    !> with random axes and in 2D: the result is finite, inside the surface, on it when the
    !> step was plastic (|f| <= 100 eps times the stress scale), coaxial with the trial, and
    !> the same in 2D as in 3D (same principal values).
    subroutine check_random_returns()
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: phi, coh, tcut, pt(3), p3(3), p2(3), off3, off2, st3(2), st2(2), scale
        real(wp) :: f3, f2, tension
        integer :: imat, n, nbad_inside, nbad_on, nbad_2d, nbad_finite, nbad_coax
        integer(i8) :: seed
        real(wp), parameter :: phis(5) = [30.0_wp, 0.0_wp, 45.0_wp, 20.0_wp, 30.0_wp]
        real(wp), parameter :: cohs(5) = [1.0e4_wp, 2.0e4_wp, 0.0_wp, 5.0e3_wp, 1.0e4_wp]
        real(wp), parameter :: psis(5) = [0.0_wp, 0.0_wp, 15.0_wp, 20.0_wp, 30.0_wp]
        real(wp), parameter :: tcuts(5) = [2.0e3_wp, 5.0e3_wp, -1.0_wp, -1.0_wp, 1.2e4_wp]
        character(len=80) :: label

        seed = 12345
        do imat = 1, size(phis)
            call make_material(mat, phis(imat), cohs(imat), psis(imat), tcuts(imat))
            phi = phis(imat)*deg
            coh = cohs(imat)
            tcut = tcuts(imat)
            tension = huge(1.0_wp)
            if (tcut >= 0.0_wp) tension = tcut
            nbad_inside = 0
            nbad_on = 0
            nbad_2d = 0
            nbad_finite = 0
            nbad_coax = 0
            do n = 1, 400
                ! hydrostatic part in [-2e5, 5e4] Pa, each principal value +-1e5 Pa about it
                pt = 2.5e5_wp*uniform(seed) - 2.0e5_wp + 1.0e5_wp*(2*[uniform(seed), &
                    uniform(seed), uniform(seed)] - 1)
                call drive(mat, pt, 3, rotation(7*uniform(seed), 7*uniform(seed), &
                    7*uniform(seed)), 0.0_wp, 3, p3, off3, st3)
                call drive(mat, pt, 2, rotation(0.0_wp, 0.0_wp, 0.0_wp), 7*uniform(seed), &
                    1 + mod(n, 3), p2, off2, st2)
                scale = max(maxval(abs(pt)), 2*coh)
                f3 = max(yield_mc(p3, phi, coh), maxval(p3) - tension)
                f2 = max(yield_mc(p2, phi, coh), maxval(p2) - tension)
                if (.not. (all(ieee_is_finite(p3)) .and. all(ieee_is_finite(p2)) .and. &
                    all(ieee_is_finite(st3)) .and. all(ieee_is_finite(st2)))) then
                    nbad_finite = nbad_finite + 1
                    cycle
                end if
                if (f3 > 100*eps*scale .or. f2 > 100*eps*scale) nbad_inside = nbad_inside + 1
                if (st3(1) > 0.0_wp .and. abs(f3) > 100*eps*scale) nbad_on = nbad_on + 1
                if (st2(1) > 0.0_wp .and. abs(f2) > 100*eps*scale) nbad_on = nbad_on + 1
                if (max(off3, off2) > 100*eps*scale) nbad_coax = nbad_coax + 1
                if (maxval(abs(p3 - p2)) > 100*eps*scale) nbad_2d = nbad_2d + 1
            end do
            write (label, "(a,f4.1,a,es8.1,a,f4.1,a,es9.1)") "random trials phi ", &
                phis(imat), " c ", coh, " psi ", psis(imat), " cut-off ", tcut
            call check(suite, nbad_finite == 0, trim(label)//": finite")
            call check(suite, nbad_inside == 0, trim(label)//": inside the surface")
            call check(suite, nbad_on == 0, trim(label)//": on the surface when plastic")
            call check(suite, nbad_coax == 0, trim(label)//": coaxial with the trial")
            call check(suite, nbad_2d == 0, trim(label)//": 2D and 3D agree")
        end do
    end subroutine check_random_returns

    !> The block update (update_stress_block: vectorised predictor, principal values and
    !> elastic test, then the return particle by particle) against update_stress one particle
    !> at a time, in 3D and 2D, for 75 particles (chunks of 32 and a remainder): random
    !> stresses about the surface (principal values about a random mean, random axes), random
    !> strain increments and spins, some particles at rest with zero stress. Both must agree
    !> to round-off (the vector acos and cos of the libmvec differ from the scalar ones in the
    !> last bits): 100 eps times the scale of the trial stress for the stress, that over G
    !> for the state; the zero stresses stay exactly zero; both see plastic and elastic
    !> particles. A second round starts from the returned stresses, on the surface, with
    !> increments of 1e-9: violations far inside the margin of the elastic test (1e-6 of the
    !> stress), which both must return. It fails when a predictor term, the margin of the
    !> elastic test or a chunk boundary is wrong.
    subroutine check_block_update()
        integer, parameter :: n = 75
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: s(6, n), sb(6, n), s0(6, n), de(6, n), om(3, n), st(2, n), stb(2, n)
        real(wp) :: st0(2, n), pt(3), d(3, 3)
        real(wp) :: r(3, 3), scale, diff
        integer :: imat, ndim, ns, j, i, nplastic, nelastic, nbad, round
        integer(i8) :: seed
        logical :: zero_ok
        real(wp), parameter :: phis(3) = [30.0_wp, 40.0_wp, 0.0_wp]
        real(wp), parameter :: cohs(3) = [0.0_wp, 1.0e4_wp, 2.0e4_wp]
        real(wp), parameter :: psis(3) = [0.0_wp, 10.0_wp, 0.0_wp]
        real(wp), parameter :: tcuts(3) = [-1.0_wp, 3.0e3_wp, 5.0e3_wp]
        character(len=80) :: label

        seed = 777
        do imat = 1, size(phis)
            call make_material(mat, phis(imat), cohs(imat), psis(imat), tcuts(imat))
            do ndim = 2, 3
                ns = merge(6, 4, ndim == 3)
                do j = 1, n
                    pt = 2.0e5_wp*uniform(seed) - 1.8e5_wp + 4.0e4_wp*(2*[uniform(seed), &
                        uniform(seed), uniform(seed)] - 1)
                    r = rotation(7*uniform(seed), 7*uniform(seed), 7*uniform(seed))
                    if (ndim == 2) r = rotation(7*uniform(seed), 0.0_wp, 0.0_wp)
                    d = 0.0_wp
                    do i = 1, 3
                        d(i, i) = pt(i)
                    end do
                    s(:, j) = matrix_to_voigt(matmul(r, matmul(d, transpose(r))))
                    do i = 1, 6
                        de(i, j) = 4.0e-3_wp*(2*uniform(seed) - 1)
                    end do
                    do i = 1, 3
                        om(i, j) = 1.0e-2_wp*(2*uniform(seed) - 1)
                    end do
                    if (ndim == 2) then
                        s(5:6, j) = 0.0_wp
                        de(3, j) = 0.0_wp
                        om(2:3, j) = 0.0_wp
                    end if
                    if (mod(j, 11) == 0) then
                        s(:, j) = 0.0_wp
                        de(:, j) = 0.0_wp
                        om(:, j) = 0.0_wp
                    end if
                end do
                st = 0.0_wp
                do round = 1, 2
                    if (round == 2) then
                        ! from the returned stresses, on the surface: increments of 1e-9,
                        ! a violation far inside the margin of the elastic test
                        do j = 1, n
                            do i = 1, 6
                                de(i, j) = 1.0e-9_wp*(2*uniform(seed) - 1)
                            end do
                            if (ndim == 2) de(3, j) = 0.0_wp
                            if (mod(j, 11) == 0) de(:, j) = 0.0_wp
                        end do
                        om = 0.0_wp
                        st0 = st
                    end if
                    sb = s
                    s0 = s
                    stb = st
                    do j = 1, n
                        call mat%update_stress(s(1:ns, j), de(1:ns, j), om(:, j), 1.0_wp, &
                            st(:, j))
                    end do
                    call mat%update_stress_block(n, sb(1:ns, :), de(1:ns, :), om, 1.0_wp, stb)
                    nbad = 0
                    if (round == 1) then
                        nplastic = count(st(1, :) > 0.0_wp)
                        nelastic = count(st(1, :) == 0.0_wp)
                    else
                        nplastic = count(st(1, :) > st0(1, :))
                        nelastic = count(st(1, :) == st0(1, :))
                    end if
                    zero_ok = .true.
                    do j = 1, n
                        ! the trial stress (a return to the apex leaves its round-off)
                        scale = max(maxval(abs(s0(1:ns, j))), young*maxval(abs(de(1:ns, j))), &
                            2*cohs(imat), 1.0_wp)
                        diff = max(maxval(abs(sb(1:ns, j) - s(1:ns, j))), &
                            shear*maxval(abs(stb(:, j) - st(:, j))))
                        if (.not. diff <= 100*eps*scale) nbad = nbad + 1
                        if (mod(j, 11) == 0) zero_ok = zero_ok .and. all(sb(1:ns, j) == 0.0_wp)
                    end do
                    write (label, "(a,i0,a,f4.1,a,es8.1,a,es8.1,a,i0)") "block update ", ndim, &
                        "D phi ", phis(imat), " c ", cohs(imat), " cut-off ", tcuts(imat), &
                        " round ", round
                    call check(suite, nbad == 0, trim(label)//": as particle by particle")
                    call check(suite, zero_ok, trim(label)//": zero stress stays zero")
                    call check(suite, nplastic > 5 .and. nelastic > 5, &
                        trim(label)//": plastic and elastic particles")
                end do
            end do
        end do
    end subroutine check_block_update

    !> The return of a whole chunk of principal stresses at once (principal_return_chunk, which
    !> the 3D block update takes without a cut-off) against the return set by set
    !> (principal_return): the same bits, for materials with an apex (phi > 0, with and
    !> without cohesion, associated and not) and without (Tresca), on random ordered
    !> principal stresses about the pyramid that reach every region (elastic, the face, both
    !> edges, the apex; counted from the returned values), with sets of exactly zero stress
    !> and chunks not full. It fails when a candidate's operations, the order of the edges
    !> or the choice of the least violating candidate differ from principal_return's.
    subroutine check_chunk_return()
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: s(material_chunk, 3), sc(material_chunk, 3), t(3), pt(3)
        logical :: plastic(material_chunk), plastic_c(material_chunk)
        integer :: imat, round, j, n, nsame, ntotal, nface, nedge, napex, nelastic
        integer(i8) :: seed
        character(len=80) :: label

        seed = 4242
        do imat = 1, size(chunk_phis)
            call make_material(mat, chunk_phis(imat), chunk_cohs(imat), chunk_psis(imat), -1.0_wp)
            nsame = 0
            ntotal = 0
            nface = 0
            nedge = 0
            napex = 0
            nelastic = 0
            do round = 1, 40
                n = material_chunk - mod(round, 7)
                do j = 1, n
                    ! some sets on an edge's line (two values equal) and some at rest
                    pt = chunk_trial_values(seed, j, 0.0_wp)
                    t(1) = maxval(pt)
                    t(3) = minval(pt)
                    t(2) = sum(pt) - t(1) - t(3)
                    s(j, :) = t
                end do
                sc = s
                call mohr_coulomb_principal_return(mat, n, s, plastic, chunked=.false.)
                call mohr_coulomb_principal_return(mat, n, sc, plastic_c, chunked=.true.)
                do j = 1, n
                    ntotal = ntotal + 1
                    if (all(transfer(s(j, :), 1_i8, 3) == transfer(sc(j, :), 1_i8, 3)) .and. &
                        (plastic(j) .eqv. plastic_c(j))) nsame = nsame + 1
                    if (.not. plastic(j)) then
                        nelastic = nelastic + 1
                    else if (abs(s(j, 1) - s(j, 3)) <= 1.0e-9_wp*maxval(abs(s(j, :))) .and. &
                        chunk_phis(imat) > 0.0_wp) then
                        napex = napex + 1
                    else if (s(j, 1) - s(j, 2) <= 1.0e-9_wp*maxval(abs(s(j, :))) .or. &
                        s(j, 2) - s(j, 3) <= 1.0e-9_wp*maxval(abs(s(j, :)))) then
                        nedge = nedge + 1
                    else
                        nface = nface + 1
                    end if
                end do
            end do
            write (label, "(a,f4.1,a,es8.1,a,f4.1)") "chunk return phi ", chunk_phis(imat), " c ", &
                chunk_cohs(imat), " psi ", chunk_psis(imat)
            call check(suite, nsame == ntotal, trim(label)//": the bits of the set-by-set return")
            call check(suite, nelastic > 20 .and. nface > 20 .and. nedge > 20 .and. &
                (napex > 5 .or. chunk_phis(imat) == 0.0_wp), trim(label)// &
                ": elastic sets, faces, edges and apexes all reached")
            if (nsame /= ntotal .or. .not. (nelastic > 20 .and. nface > 20 .and. nedge > 20)) &
                write (*, "(a,6(1x,i0))") "  same, total, elastic, face, edge, apex:", nsame, &
                ntotal, nelastic, nface, nedge, napex
        end do
    end subroutine check_chunk_return

    !> The 3D return of a chunk with the principal values and corrections of the well
    !> separated stresses all at once (the block update's way) against the same return with
    !> each particle's values and correction one by one (principal_values_3d,
    !> correct_stress_3d): the same bits of stress and state, for four materials without a
    !> cut-off, on random trial stresses with random axes about the pyramid, some with two
    !> principal values close or equal (those take Jacobi's eigenvectors in both, mixed with
    !> the others in a chunk), some zero, chunks not full. It fails when an operation of the
    !> refinement, of the choice of its pair or column, of the correction or of the plastic
    !> strain differs from the particle-by-particle one, or a lane is stored to another one.
    subroutine check_chunk_return_3d()
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: t(material_chunk, 6), s(6, material_chunk), sv(6, material_chunk)
        real(wp) :: st(2, material_chunk), stv(2, material_chunk), pt(3), r(3, 3), d(3, 3)
        integer :: imat, round, j, i, n, nsame, ntotal, nplastic, nclose
        integer(i8) :: seed
        character(len=80) :: label

        seed = 5151
        do imat = 1, size(chunk_phis)
            call make_material(mat, chunk_phis(imat), chunk_cohs(imat), chunk_psis(imat), -1.0_wp)
            nsame = 0
            ntotal = 0
            nplastic = 0
            nclose = 0
            do round = 1, 40
                n = material_chunk - mod(round, 7)
                do j = 1, n
                    ! some with a close or repeated pair (Jacobi), some at rest
                    pt = chunk_trial_values(seed, j, 1.0e-6_wp)
                    if (mod(j, 5) == 0) nclose = nclose + 1
                    r = rotation(7*uniform(seed), 7*uniform(seed), 7*uniform(seed))
                    d = 0.0_wp
                    do i = 1, 3
                        d(i, i) = pt(i)
                    end do
                    t(j, :) = matrix_to_voigt(matmul(r, matmul(d, transpose(r))))
                end do
                st = 0.0_wp
                stv = 0.0_wp
                call mohr_coulomb_return_chunk_3d(mat, n, t, s(:, 1:n), st(:, 1:n), .false.)
                call mohr_coulomb_return_chunk_3d(mat, n, t, sv(:, 1:n), stv(:, 1:n), .true.)
                do j = 1, n
                    ntotal = ntotal + 1
                    if (all(transfer(s(:, j), 1_i8, 6) == transfer(sv(:, j), 1_i8, 6)) .and. &
                        all(transfer(st(:, j), 1_i8, 2) == transfer(stv(:, j), 1_i8, 2))) &
                        nsame = nsame + 1
                    if (st(1, j) > 0.0_wp) nplastic = nplastic + 1
                end do
            end do
            write (label, "(a,f4.1,a,es8.1,a,f4.1)") "3D chunk return phi ", chunk_phis(imat), " c ", &
                chunk_cohs(imat), " psi ", chunk_psis(imat)
            call check(suite, nsame == ntotal, trim(label)// &
                ": the bits of the particle-by-particle values and corrections")
            call check(suite, nplastic > ntotal/4 .and. ntotal - nplastic > ntotal/10 .and. &
                nclose > 100, trim(label)//": plastic, elastic and close pairs all reached")
            if (nsame /= ntotal) write (*, "(a,3(1x,i0))") "  same, total, plastic:", nsame, &
                ntotal, nplastic
        end do
    end subroutine check_chunk_return_3d

    !> Random principal values about the pyramid for set j of a chunk test: every fifth with
    !> its first two values `close` apart (relative; 0: equal), every seventh with the last two
    !> equal, every thirteenth zero.
    function chunk_trial_values(seed, j, close) result(pt)
        integer(i8), intent(inout) :: seed
        integer, intent(in) :: j
        real(wp), intent(in) :: close
        real(wp) :: pt(3)

        pt = 2.0e5_wp*uniform(seed) - 1.5e5_wp + 6.0e4_wp*(2*[uniform(seed), uniform(seed), &
            uniform(seed)] - 1)
        if (mod(j, 5) == 0) then
            if (close > 0.0_wp) then
                pt(2) = pt(1)*(1.0_wp + close*uniform(seed))
            else
                pt(2) = pt(1)
            end if
        end if
        if (mod(j, 7) == 0) pt(2) = pt(3)
        if (mod(j, 13) == 0) pt = 0.0_wp
    end function chunk_trial_values

    !> Nearly repeated principal trial stresses, 3D with random axes: two of them a gap
    !> g |p|max apart (g = 0, 1e-12, 1e-8, 1e-4, 5e-4, 1.05e-3, 1.5e-3, 1e-2; the upper or the
    !> lower pair), the third and the mean random. The default path (spectral projectors where
    !> the gap exceeds 1e-3 of the largest stress component, Jacobi below) must give the
    !> stress and state of the Jacobi path (`jacobi_only`) and a result inside the surface, on
    !> it when plastic (and, above the threshold, differ in the last bits somewhere: the
    !> projectors were used). Tol: both paths are exact to a few eps |sigma| for any gap (the
    !> ill-conditioned directions of a close pair only multiply the difference of its
    !> corrections, at most the gap), so 100 eps |sigma| for the stresses and f, that over G
    !> for the state. It fails without the Jacobi fallback (errors up to 0.6 |sigma| at
    !> g <= 1e-12) and, just above the threshold, without the refinement of the trigonometric
    !> eigenvalues (their error eps |sigma| rho / g reaches 100 eps |sigma| there).
    subroutine check_close_eigenvalues()
        type(mohr_coulomb_material_type) :: mat, ref
        real(wp) :: phi, coh, tcut, tension, p(3), r(3, 3), d(3, 3), trial(6), s(6), sr(6)
        real(wp) :: st(2), str(2), m(3, 3), pr(3), scale, f, h, spread, diff, diff_max, f_max
        integer :: imat, ig, n, i, nbad_same, nbad_inside, nbad_on, nbad_finite, nplastic
        integer :: ndistinct
        integer(i8) :: seed
        real(wp), parameter :: gaps(8) = [0.0_wp, 1.0e-12_wp, 1.0e-8_wp, 1.0e-4_wp, &
            5.0e-4_wp, 1.05e-3_wp, 1.5e-3_wp, 1.0e-2_wp]
        real(wp), parameter :: phis(4) = [30.0_wp, 30.0_wp, 45.0_wp, 20.0_wp]
        real(wp), parameter :: cohs(4) = [0.0_wp, 1.0e4_wp, 0.0_wp, 5.0e3_wp]
        real(wp), parameter :: psis(4) = [0.0_wp, 10.0_wp, 15.0_wp, 20.0_wp]
        real(wp), parameter :: tcuts(4) = [-1.0_wp, 5.0e3_wp, -1.0_wp, 2.0e3_wp]
        character(len=100) :: label

        seed = 2024
        do imat = 1, size(phis)
            call make_material(mat, phis(imat), cohs(imat), psis(imat), tcuts(imat))
            ref = mat
            ref%jacobi_only = .true.
            phi = phis(imat)*deg
            coh = cohs(imat)
            tcut = tcuts(imat)
            tension = huge(1.0_wp)
            if (tcut >= 0.0_wp) tension = tcut
            do ig = 1, size(gaps)
                nbad_same = 0
                nbad_inside = 0
                nbad_on = 0
                nbad_finite = 0
                nplastic = 0
                ndistinct = 0
                diff_max = 0.0_wp
                f_max = 0.0_wp
                do n = 1, 1000
                    ! mean in [-1e5, 5e4] Pa, extreme values 2e4 to 1e5 Pa about it
                    h = 1.5e5_wp*uniform(seed) - 1.0e5_wp
                    spread = 2.0e4_wp + 8.0e4_wp*uniform(seed)
                    p = [h + spread, h + spread*(2*uniform(seed) - 1), h - spread]
                    scale = maxval(abs(p))
                    if (mod(n, 2) == 0) then
                        p(2) = p(1) - gaps(ig)*scale
                    else
                        p(2) = p(3) + gaps(ig)*scale
                    end if
                    r = rotation(7*uniform(seed), 7*uniform(seed), 7*uniform(seed))
                    d = 0.0_wp
                    do i = 1, 3
                        d(i, i) = p(i)
                    end do
                    trial = matrix_to_voigt(matmul(r, matmul(d, transpose(r))))
                    s = trial
                    sr = trial
                    st = 0.0_wp
                    str = 0.0_wp
                    call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
                        0.0_wp], zero3, 1.0_wp, st)
                    call ref%update_stress(sr, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, &
                        0.0_wp], zero3, 1.0_wp, str)
                    if (.not. (all(ieee_is_finite(s)) .and. all(ieee_is_finite(st)))) then
                        nbad_finite = nbad_finite + 1
                        cycle
                    end if
                    if (any(s /= sr)) ndistinct = ndistinct + 1
                    diff = max(maxval(abs(s - sr)), shear*maxval(abs(st - str)))
                    diff_max = max(diff_max, diff/scale)
                    if (diff > 100*eps*scale) nbad_same = nbad_same + 1
                    ! principal values of the result in the frame of the trial (coaxial)
                    m = matmul(transpose(r), matmul(voigt_to_matrix(s), r))
                    pr = [m(1, 1), m(2, 2), m(3, 3)]
                    f = max(yield_mc(pr, phi, coh), maxval(pr) - tension)
                    if (f > 100*eps*scale) nbad_inside = nbad_inside + 1
                    if (st(1) > 0.0_wp) then
                        nplastic = nplastic + 1
                        f_max = max(f_max, abs(f)/scale)
                        if (abs(f) > 100*eps*scale) nbad_on = nbad_on + 1
                    end if
                end do
                write (label, "(a,f4.1,a,es8.1,a,es8.1,a)") "close eigenvalues phi ", &
                    phis(imat), " cut-off ", tcut, " gap ", gaps(ig), ":"
                call check(suite, nbad_finite == 0, trim(label)//" finite")
                call check(suite, nplastic >= 250, trim(label)//" mostly plastic")
                call check(suite, nbad_same == 0, trim(label)//" closed form = Jacobi")
                ! above the threshold the paths differ in the last bits: the projectors ran
                if (gaps(ig) > 1.0e-3_wp) call check(suite, ndistinct > 0, &
                    trim(label)//" closed form taken")
                call check(suite, nbad_inside == 0, trim(label)//" inside the surface")
                call check(suite, nbad_on == 0, trim(label)//" on the surface when plastic")
                if (nbad_same + nbad_inside + nbad_on > 0) write (*, "(a,2es10.2)") &
                    "    largest difference and |f| / scale:", diff_max, f_max
            end do
        end do
    end subroutine check_close_eigenvalues

    !> Uniform number in (0, 1) from the Park-Miller minimal standard generator (64-bit
    !> integers, no overflow); reproducible on every platform.
    real(wp) function uniform(seed)
        integer(i8), intent(inout) :: seed
        integer(i8), parameter :: mult = 16807_i8, modulus = 2147483647_i8
        seed = mod(mult*seed, modulus)
        uniform = real(seed, wp)/real(modulus, wp)
    end function uniform

    !> A yielded 2D stress (on the face, s_zz intermediate) turned rigidly by 90 degrees in
    !> 20000 spin-only steps must become R s R^T with the invariants kept; forward Euler turns
    !> with a relative error of order theta^2 / N (as for the elastic material), which also
    !> bounds the small returns it triggers.
    subroutine check_rigid_rotation_2d()
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: s(4), s0(4), state(2), theta, omega, c, sn, tol_rot
        integer :: k
        integer, parameter :: nstep = 20000

        call make_material(mat, 30.0_wp, 1.0e4_wp, 0.0_wp, -1.0_wp)
        ! bring a stress onto the surface first
        s = [-1.0e5_wp, -1.0e5_wp, -1.0e5_wp, 0.0_wp]
        state = 0.0_wp
        call mat%update_stress(s, [2.0e-2_wp, -2.0e-2_wp, 0.0_wp, 0.0_wp], zero3, 1.0_wp, state)
        call check(suite, state(1) > 0.0_wp, "2D rotation: the initial stress is yielded")
        s0 = s
        theta = pi/2
        omega = -theta/nstep
        do k = 1, nstep
            call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [omega, 0.0_wp, &
                0.0_wp], 1.0_wp, state)
        end do
        c = cos(theta)
        sn = sin(theta)
        tol_rot = 2*theta**2/nstep*maxval(abs(s0))
        call check_close(suite, s(1), s0(1)*c*c + s0(2)*sn*sn - 2*s0(4)*c*sn, tol_rot, &
            "2D rigid rotation of a yielded stress: s_xx")
        call check_close(suite, s(2), s0(1)*sn*sn + s0(2)*c*c + 2*s0(4)*c*sn, tol_rot, &
            "2D rigid rotation of a yielded stress: s_yy")
        call check_close(suite, s(3), s0(3), tol_rot, "2D rigid rotation keeps s_zz")
        call check_close(suite, s(1) + s(2), s0(1) + s0(2), tol_rot, &
            "2D rigid rotation keeps the trace")
        call check_close(suite, hypot(0.5_wp*(s(1) - s(2)), s(4)), &
            hypot(0.5_wp*(s0(1) - s0(2)), s0(4)), tol_rot, "2D rigid rotation keeps the radius")
    end subroutine check_rigid_rotation_2d

    !> 3D: a yielded general stress turned about x by pi/3 must become R s R^T.
    subroutine check_rigid_rotation_3d()
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: s(6), state(2), theta, om, r(3, 3), a(3, 3), b(3, 3), tol_rot
        integer :: k
        integer, parameter :: nstep = 20000

        call make_material(mat, 30.0_wp, 1.0e4_wp, 10.0_wp, -1.0_wp)
        s = [-3.0e5_wp, -2.0e5_wp, -1.0e5_wp, 4.0e4_wp, 2.0e4_wp, -1.0e4_wp]
        state = 0.0_wp
        call mat%update_stress(s, [3.0e-2_wp, 0.0_wp, -3.0e-2_wp, 5.0e-3_wp, 0.0_wp, 0.0_wp], &
            zero3, 1.0_wp, state)
        call check(suite, state(1) > 0.0_wp, "3D rotation: the initial stress is yielded")
        a = voigt_to_matrix(s)
        theta = pi/3
        om = theta/nstep
        do k = 1, nstep
            call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                [0.0_wp, -om, 0.0_wp], 1.0_wp, state)
        end do
        r = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, cos(theta), sin(theta), &
            0.0_wp, -sin(theta), cos(theta)], [3, 3])
        b = matmul(r, matmul(a, transpose(r)))
        tol_rot = 2*theta**2/nstep*maxval(abs(a))*3
        call check(suite, maxval(abs(voigt_to_matrix(s) - b)) <= tol_rot, &
            "3D rigid rotation of a yielded stress gives R s R^T")
        call check_close(suite, s(1) + s(2) + s(3), a(1, 1) + a(2, 2) + a(3, 3), tol_rot, &
            "3D rigid rotation keeps the trace")
    end subroutine check_rigid_rotation_3d

    !> Degenerate cases give finite, exact answers (under the FPE traps of the Debug build):
    !> phi = 0 and c = 0 (no strength: the stress becomes isotropic with the trial mean),
    !> c = 0 in tension (the apex is the zero stress), zero increments on zero, isotropic and
    !> yielded stresses, isotropic tension beyond the apex and beyond the cut-off (a triple
    !> eigenvalue), Tresca with a cut-off.
    subroutine check_degenerate()
        type(mohr_coulomb_material_type) :: mat
        real(wp) :: s6(6), s4(4), state(2), mean, before(6)

        ! phi = 0, c = 0
        call make_material(mat, 0.0_wp, 0.0_wp, 0.0_wp, -1.0_wp)
        s6 = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(s6, [1.0e-3_wp, -2.0e-3_wp, 5.0e-4_wp, 1.0e-3_wp, 0.0_wp, &
            -3.0e-4_wp], zero3, 1.0_wp, state)
        mean = bulk*(1.0e-3_wp - 2.0e-3_wp + 5.0e-4_wp)
        call check(suite, all(ieee_is_finite(s6)) .and. all(ieee_is_finite(state)), &
            "phi = 0, c = 0: finite")
        ! round-off of the return: 100 eps times the trial stress, |sigma_t| <= E |de|_max
        call check(suite, maxval(abs(s6(1:3) - mean)) <= 100*eps*young*2.0e-3_wp .and. &
            maxval(abs(s6(4:6))) <= 100*eps*young*2.0e-3_wp, &
            "phi = 0, c = 0: isotropic stress with the trial mean")
        s4 = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(s4, [1.0e-3_wp, -2.0e-3_wp, 0.0_wp, 1.0e-3_wp], zero3, 1.0_wp, &
            state)
        mean = bulk*(1.0e-3_wp - 2.0e-3_wp)
        call check(suite, maxval(abs(s4(1:3) - mean)) <= 100*eps*young*2.0e-3_wp .and. &
            abs(s4(4)) <= 100*eps*young*2.0e-3_wp, &
            "2D phi = 0, c = 0: isotropic with the trial mean")
        ! c = 0 in tension: the apex is zero stress
        call make_material(mat, 30.0_wp, 0.0_wp, 10.0_wp, -1.0_wp)
        s6 = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(s6, [1.0e-3_wp, 2.0e-3_wp, 5.0e-4_wp, 1.0e-4_wp, 0.0_wp, &
            0.0_wp], zero3, 1.0_wp, state)
        call check(suite, all(abs(s6) <= 100*eps*young*2.0e-3_wp), &
            "c = 0: tension returns to the zero apex")
        call check(suite, all(ieee_is_finite(state)) .and. state(2) > 0.0_wp, &
            "c = 0: finite dilation at the apex")
        ! zero increments on zero stress with c = 0: nothing happens
        s6 = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(s6, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, &
            1.0_wp, state)
        call check(suite, all(s6 == 0.0_wp) .and. all(state == 0.0_wp), &
            "zero increment on zero stress stays zero")
        s4 = 0.0_wp
        call mat%update_stress(s4, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, 1.0_wp, state)
        call check(suite, all(s4 == 0.0_wp) .and. all(state == 0.0_wp), &
            "2D zero increment on zero stress stays zero")
        ! zero increment on an isotropic compression: unchanged, exactly
        s6 = [-1.0e5_wp, -1.0e5_wp, -1.0e5_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        call mat%update_stress(s6, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, &
            1.0_wp, state)
        call check(suite, all(s6 == [-1.0e5_wp, -1.0e5_wp, -1.0e5_wp, 0.0_wp, 0.0_wp, &
            0.0_wp]) .and. all(state == 0.0_wp), "zero increment on an isotropic stress")
        ! zero increment on a yielded stress: unchanged to round-off, no new plastic strain
        s6 = [-1.0e5_wp, -1.0e5_wp, -1.0e5_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        call mat%update_stress(s6, [1.0e-2_wp, 0.0_wp, -1.0e-2_wp, 3.0e-3_wp, 1.0e-3_wp, &
            0.0_wp], zero3, 1.0_wp, state)
        before = s6
        mean = state(1)
        call mat%update_stress(s6, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, &
            1.0_wp, state)
        call check(suite, all(abs(s6 - before) <= 100*eps*maxval(abs(before))) .and. &
            abs(state(1) - mean) <= 100*eps*maxval(abs(before))/shear, &
            "zero increment on a yielded stress")
        ! isotropic tension beyond the apex, phi = 30, c = 10 kPa, no cut-off
        call make_material(mat, 30.0_wp, 1.0e4_wp, 0.0_wp, -1.0_wp)
        s6 = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(s6, [1.0e-2_wp, 1.0e-2_wp, 1.0e-2_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
            zero3, 1.0_wp, state)
        call check(suite, all(abs(s6(1:3) - 1.0e4_wp/tan(30*deg)) <= 100*eps*3*bulk*1.0e-2_wp) &
            .and. all(s6(4:6) == 0.0_wp), "isotropic tension returns to the apex")
        call check_close(suite, state(1), 0.0_wp, 100*eps*3*bulk*1.0e-2_wp/shear, &
            "isotropic tension to the apex: no plastic shear strain")
        ! isotropic tension beyond the cut-off: the corner (t, t, t), 2D and 3D
        call make_material(mat, 30.0_wp, 1.0e4_wp, 0.0_wp, 3.0e3_wp)
        s6 = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(s6, [1.0e-2_wp, 1.0e-2_wp, 1.0e-2_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
            zero3, 1.0_wp, state)
        call check(suite, all(abs(s6(1:3) - 3.0e3_wp) <= 100*eps*3*bulk*1.0e-2_wp) .and. &
            all(s6(4:6) == 0.0_wp), "isotropic tension returns to the cut-off corner (3D)")
        s4 = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(s4, [1.0e-2_wp, 1.0e-2_wp, 1.0e-2_wp, 0.0_wp], zero3, 1.0_wp, &
            state)
        call check(suite, all(abs(s4(1:3) - 3.0e3_wp) <= 100*eps*3*bulk*1.0e-2_wp) .and. &
            s4(4) == 0.0_wp, "isotropic tension returns to the cut-off corner (2D)")
        ! Tresca with a cut-off: uniaxial tension
        call make_material(mat, 0.0_wp, 2.0e4_wp, 0.0_wp, 5.0e3_wp)
        s6 = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(s6, [1.0e-2_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
            zero3, 1.0_wp, state)
        call check(suite, all(ieee_is_finite(s6)) .and. abs(maxval(s6(1:3)) - 5.0e3_wp) <= &
            100*eps*young*1.0e-2_wp*2, "Tresca with a cut-off: largest stress is sigma_t")
    end subroutine check_degenerate

    !> Softening in conventional triaxial compression (p0 = 100 kPa): phi 35 -> 25 deg,
    !> c 20 -> 2 kPa, psi 10 -> 0 deg. Each plastic step returns to the planes of the start of
    !> the step: f(sigma_k; phi, c of eps_q,k-1) = 0 to round-off. At large plastic shear
    !> strain the strength is the residual one, q_r = 2 (c_r cos phi_r + p0 sin phi_r) /
    !> (1 - sin phi_r): exactly after the softening strain for the linear law (tol as in the
    !> triaxial test), and within the remaining decay 10 (q_p - q_r) exp(-eps_q / eta) for the
    !> exponential law (dq/dw <= 10 (q_p - q_r) over the decay w of the parameters).
    subroutine check_softening(law)
        integer, intent(in) :: law
        type(mohr_coulomb_material_type) :: mat
        real(wp), parameter :: phi_p = 35.0_wp, phi_rd = 25.0_wp, c_p = 2.0e4_wp, c_r = 2.0e3_wp
        real(wp), parameter :: eta = 1.0e-2_wp
        real(wp) :: stress(6), state(2), de(6), q, qr, qp, tol_q, fmax, phi, coh, w, eq0
        integer :: k
        integer, parameter :: nsteps = 2000
        real(wp), parameter :: dea = -2.0e-4_wp
        logical :: ok, all_ok
        character(len=40) :: label

        label = merge("softening linear     ", "softening exponential", law == softening_linear)
        call make_material(mat, phi_p, c_p, 10.0_wp, -1.0_wp, law, phi_rd, c_r, 0.0_wp, eta)
        stress = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        state = 0.0_wp
        all_ok = .true.
        fmax = 0.0_wp
        do k = 1, nsteps
            de = [0.0_wp, 0.0_wp, dea, 0.0_wp, 0.0_wp, 0.0_wp]
            eq0 = state(1)
            call mixed_step(mat, stress, state, de, 1, 2, constant_cell, -p0, &
                2*(shear + lame), ok)
            all_ok = all_ok .and. ok
            if (state(1) > eq0) then
                if (law == softening_linear) then
                    w = min(eq0/eta, 1.0_wp)
                else
                    w = 1 - exp(-eq0/eta)
                end if
                phi = (phi_p + w*(phi_rd - phi_p))*deg
                coh = c_p + w*(c_r - c_p)
                fmax = max(fmax, abs(yield_mc(stress(1:3), phi, coh)))
            end if
        end do
        q = stress(1) - stress(3)
        qp = 2*(c_p*cos(phi_p*deg) + p0*sin(phi_p*deg))/(1 - sin(phi_p*deg))
        qr = 2*(c_r*cos(phi_rd*deg) + p0*sin(phi_rd*deg))/(1 - sin(phi_rd*deg))
        tol_q = 3*tol_mixed + 100*eps*(p0 + qp)
        if (law == softening_exponential) tol_q = tol_q + 10*(qp - qr)*exp(-state(1)/eta)
        call check(suite, all_ok, trim(label)//": mixed control converged")
        call check(suite, fmax <= 100*eps*(p0 + qp), &
            trim(label)//": on the surface of the start-of-step strength")
        call check(suite, state(1) > 20*eta, trim(label)//": large plastic shear strain")
        call check_close(suite, q, qr, tol_q, trim(label)//": residual strength")
    end subroutine check_softening

end program test_mpm_material_mohr_coulomb
