!> Drucker-Prager material: element tests against Mohr-Coulomb closed forms (plane strain,
!> triaxial compression and extension), the flow rule, the exact returns (cone, tension plane,
!> corner, apex), isotropic compression, objectivity, degenerate parameters and softening.
!>
!> Mixed stress/strain control (a confining stress held while an axial strain is driven) is
!> solved per step by the secant method on the lateral strain increment to a residual of
!> tol_mixed = 1e-9 p0; strength checks allow a few times that, scaled by the slope of the
!> yield surface.
program test_mpm_material_drucker_prager
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_softening, only: softening_none, softening_linear, softening_exponential
    use mpm_strength, only: strength_type
    use mpm_material_drucker_prager, only: drucker_prager_material_type, &
        new_drucker_prager_material, drucker_prager_cone, cone_plane_strain, cone_compression, &
        cone_extension
    implicit none

    !> The strength and cone of a test material (E, nu of this test, rho = 2000 kg/m3).
    type :: material_spec_type
        type(strength_type) :: strength
            !! friction, cohesion, dilatancy, cut-off, softening
        integer :: cone = cone_plane_strain
            !! the cone
    end type material_spec_type

    type(test_suite_type) :: suite
    real(wp), parameter :: pi = acos(-1.0_wp), deg = pi/180.0_wp
    real(wp), parameter :: young = 1.0e7_wp, poisson = 0.3_wp
    real(wp), parameter :: p0 = 1.0e5_wp      ! confining pressure [Pa]
    real(wp), parameter :: coh = 1.0e4_wp     ! cohesion [Pa]
    real(wp), parameter :: tol_mixed = 1.0e-9_wp*p0
    real(wp), parameter :: zero3(3) = 0.0_wp
    real(wp), parameter :: eps = epsilon(1.0_wp)

    call new_suite(suite, "mpm_material_drucker_prager")
    call check_cone_constants()
    call check_plane_strain(0.0_wp)
    call check_plane_strain(15.0_wp)
    call check_plane_strain(30.0_wp)
    call check_triaxial_compression()
    call check_triaxial_extension()
    call check_returns()
    call check_continuity()
    call check_isotropic_compression()
    call check_frame_invariance()
    call check_rigid_rotation_2d()
    call check_rigid_rotation_3d()
    call check_degenerate()
    call check_softening(softening_linear)
    call check_softening(softening_exponential)
    call check_block_update()
    call finish(suite)

contains

    !> The plane-strain cone for psi = phi is the associated match of REFERENCES section 5,
    !> tan(beta) = 3 tan(phi)/sqrt(9 + 12 tan(phi)^2), k = 3 c/sqrt(9 + 12 tan(phi)^2), and for
    !> psi = 0 the classic alpha = sin(phi), k = c cos(phi); the compression cone passes
    !> through the triaxial compression corner, q = sqrt(3) (k + alpha p). Algebraic
    !> identities: tol 10 eps.
    subroutine check_cone_constants()
        real(wp), parameter :: phi = 30.0_wp*deg
        real(wp) :: alpha, k, apsi, root

        call drucker_prager_cone(cone_plane_strain, phi, coh, phi, alpha, k, apsi)
        root = sqrt(9 + 12*tan(phi)**2)
        call check_close(suite, alpha, 3*tan(phi)/root, 10*eps, "plane strain psi = phi: alpha")
        call check_close(suite, k, 3*coh/root, 10*eps*coh, "plane strain psi = phi: k")
        call check_close(suite, apsi, alpha, 10*eps, "plane strain psi = phi: associated")
        call drucker_prager_cone(cone_plane_strain, phi, coh, 0.0_wp, alpha, k, apsi)
        call check_close(suite, alpha, sin(phi), 10*eps, "plane strain psi = 0: alpha = sin")
        call check_close(suite, k, coh*cos(phi), 10*eps*coh, "plane strain psi = 0: k = c cos")
        call check_close(suite, apsi, 0.0_wp, 0.0_wp, "plane strain psi = 0: alpha_psi = 0")
        call drucker_prager_cone(cone_compression, phi, coh, phi, alpha, k, apsi)
        call check_close(suite, sqrt(3.0_wp)*(k + alpha*p0), &
            6*(coh*cos(phi) + p0*sin(phi))/(3 - sin(phi)), 10*eps*p0, &
            "compression cone: q at mean pressure p")
    end subroutine check_cone_constants

    !> Plane-strain compression (eps_zz = 0 by the 2D formulation), sigma_xx = -p0 held,
    !> eps_yy driven: at steady plastic flow the plane-strain cone must give the Mohr-Coulomb
    !> plane-strain strength sigma_1 = p0 N + 2 c sqrt(N), N = (1 + sin phi)/(1 - sin phi)
    !> (compression positive), for psi = 0, psi = phi/2 and psi = phi (associated).
    !>
    !> Why it must hold: at steady flow the stress no longer changes, so the plastic eps_zz
    !> rate is zero (total eps_zz = 0), which fixes s_zz = -2 alpha_psi sqrt(J2)/3; with the
    !> cone constants of `drucker_prager_cone` the in-plane Mohr circle then touches the
    !> Mohr-Coulomb line exactly (see there). The plastic strain increments must also give
    !> the Mohr-Coulomb plane-strain dilatancy d eps_v = sin(psi) (d eps_1 - d eps_3).
    !> The steady state is approached exponentially: s_zz relaxes towards its steady value
    !> over a plastic strain of about sqrt(J2)/G ~ 0.03 (about 0.02 is seen for psi = 0, less
    !> for psi > 0). The gap at first yield, ~4e4 Pa, is thus below 4e4 exp(-0.4/0.02) ~ 1e-4 Pa
    !> after an axial strain of 0.4, inside the mixed-control tolerance 10 N tol_mixed ~ 3e-3 Pa.
    subroutine check_plane_strain(psi_deg)
        real(wp), intent(in) :: psi_deg
            !! dilatancy angle [deg]

        type(drucker_prager_material_type) :: mat
        real(wp), parameter :: phi = 30.0_wp*deg, de = -2.0e-4_wp
        integer, parameter :: nstep = 2000
        real(wp) :: s(4), st(2), x, nphi, sig1, prev(4), dep(3), spsi
        logical :: ok
        integer :: i
        character(len=40) :: tag

        write (tag, "(a,f4.1,a)") "plane strain psi=", psi_deg, ":"
        call new_material(mat, make_spec(phi, coh, psi_deg*deg, &
            cone_plane_strain))
        s = [-p0, -p0, -p0, 0.0_wp]
        st = 0.0_wp
        x = 0.0_wp
        ok = .true.
        do i = 1, nstep
            prev = s
            call mixed_step(mat, s, st, [0.0_wp, de, 0.0_wp, 0.0_wp], &
                [.true., .false., .false., .false.], -p0, x, ok)
        end do
        call check(suite, ok, trim(tag)//" mixed control converged")
        nphi = (1 + sin(phi))/(1 - sin(phi))
        sig1 = p0*nphi + 2*coh*sqrt(nphi)
        ! sigma_yy depends on sigma_xx with slope N <= 3 on the Mohr-Coulomb line
        call check_close(suite, s(2), -sig1, 10*nphi*tol_mixed, &
            trim(tag)//" sigma_yy = MC plane-strain strength")
        call check(suite, maxval(abs(s - prev)) <= 10*tol_mixed, &
            trim(tag)//" steady state reached")
        ! last step: plastic strain = total - elastic (elastic part of the stress change)
        dep = [x, de, 0.0_wp] - compliance(s(1:3) - prev(1:3))
        spsi = sin(psi_deg*deg)
        ! the elastic part of the last step is at most 10 tol_mixed / E ~ 1e-10 against
        ! |de| = 2e-4: relative 5e-7
        call check_close(suite, (dep(1) + dep(2) + dep(3))/(dep(1) - dep(2)), spsi, 1.0e-6_wp, &
            trim(tag)//" d eps_v^p / (d eps_1^p - d eps_3^p) = sin(psi)")
        call check_close(suite, dep(3)/abs(de), 0.0_wp, 1.0e-6_wp, &
            trim(tag)//" no plastic eps_zz at steady state")
    end subroutine check_plane_strain

    !> Triaxial compression (3D, sigma_xx = sigma_zz = -p0 held, eps_yy driven) with the
    !> compression cone: q = 2 (c cos phi + p0 sin phi)/(1 - sin phi), which is
    !> 6 (c cos phi + p sin phi)/(3 - sin phi) with p the mean pressure at failure (MC
    !> compression meridian). The flow rule gives d eps_v^p / d eps_q^p = 6 sin psi/(3 - sin psi)
    !> and d eps_v^p / d eps_yy^p = -2 sin psi/(1 - sin psi) (MC at the compression corner).
    subroutine check_triaxial_compression()
        type(drucker_prager_material_type) :: mat
        real(wp), parameter :: phi = 30.0_wp*deg, psi = 10.0_wp*deg, de = -2.0e-4_wp
        integer, parameter :: nstep = 600
        real(wp) :: s(6), st(2), x, q, qmc, p, eps_tot(3), epl(3), eq, ev
        logical :: ok
        integer :: i

        call new_material(mat, make_spec(phi, coh, psi, cone_compression))
        s = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        st = 0.0_wp
        x = 0.0_wp
        ok = .true.
        eps_tot = compliance(s(1:3))
        do i = 1, nstep
            call mixed_step(mat, s, st, [0.0_wp, de, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                [.true., .false., .true., .false., .false., .false.], -p0, x, ok)
            eps_tot = eps_tot + [x, de, x]
        end do
        call check(suite, ok, "triaxial compression: mixed control converged")
        q = s(1) - s(2)
        qmc = 2*(coh*cos(phi) + p0*sin(phi))/(1 - sin(phi))
        ! q depends on sigma_xx with slope (1 + sin)/(1 - sin) + 1 < 4
        call check_close(suite, q, qmc, 40*tol_mixed, "triaxial compression q = MC (cell p0)")
        p = -(s(1) + s(2) + s(3))/3
        call check_close(suite, q, 6*(coh*cos(phi) + p*sin(phi))/(3 - sin(phi)), 40*tol_mixed, &
            "triaxial compression q = 6 (c cos + p sin)/(3 - sin) at failure mean p")
        ! plastic strain = total - elastic; stress errors ~tol_mixed give ~1e-11 strain against
        ! plastic strains ~0.1: relative 1e-9 on the ratios
        epl = eps_tot - compliance(s(1:3))
        ev = sum(epl)
        eq = 2.0_wp/3.0_wp*abs(epl(1) - epl(2))
        call check_close(suite, ev/eq, 6*sin(psi)/(3 - sin(psi)), 1.0e-8_wp, &
            "triaxial compression: eps_v^p / eps_q^p = 6 sin psi/(3 - sin psi)")
        call check_close(suite, ev/epl(2), -2*sin(psi)/(1 - sin(psi)), 1.0e-8_wp, &
            "triaxial compression: eps_v^p / eps_axial^p = -2 sin psi/(1 - sin psi) (MC)")
        call check_close(suite, st(1), eq, 1.0e-8_wp*eq, "state(1) = eps_q^p")
        call check_close(suite, st(2), ev, 1.0e-8_wp*eq, "state(2) = eps_v^p")
    end subroutine check_triaxial_compression

    !> Triaxial extension (3D, sigma_xx = sigma_zz = -p0 held, the axial stress relieved) with
    !> the extension cone: q = 2 (c cos phi + p0 sin phi)/(1 + sin phi), which is
    !> 6 (c cos phi + p sin phi)/(3 + sin phi) at the failure mean pressure p (MC extension).
    subroutine check_triaxial_extension()
        type(drucker_prager_material_type) :: mat
        real(wp), parameter :: phi = 30.0_wp*deg, de = 2.0e-4_wp
        integer, parameter :: nstep = 600
        real(wp) :: s(6), st(2), x, q, p
        logical :: ok
        integer :: i

        call new_material(mat, make_spec(phi, coh, 0.0_wp, cone_extension))
        s = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        st = 0.0_wp
        x = 0.0_wp
        ok = .true.
        do i = 1, nstep
            call mixed_step(mat, s, st, [0.0_wp, de, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                [.true., .false., .true., .false., .false., .false.], -p0, x, ok)
        end do
        call check(suite, ok, "triaxial extension: mixed control converged")
        call check(suite, st(1) > 0.0_wp, "triaxial extension: reached plastic flow")
        q = s(2) - s(1)
        call check_close(suite, q, 2*(coh*cos(phi) + p0*sin(phi))/(1 + sin(phi)), &
            40*tol_mixed, "triaxial extension q = MC (cell p0)")
        p = -(s(1) + s(2) + s(3))/3
        call check_close(suite, q, 6*(coh*cos(phi) + p*sin(phi))/(3 + sin(phi)), 40*tol_mixed, &
            "triaxial extension q = 6 (c cos + p sin)/(3 + sin) at failure mean p")
    end subroutine check_triaxial_extension

    !> Single steps that end on the cone, the tension plane, their corner and the apex. The
    !> stress must lie on the active surface(s) to round-off; tol = 100 eps * scale, scale
    !> the largest trial stress: the return and the invariants are a few tens of operations
    !> on numbers of at most that size. The cone return must follow the flow rule:
    !> deviator parallel to the trial one and (m_tr - m)/K = alpha_psi (rho_tr - rho)/G.
    subroutine check_returns()
        type(drucker_prager_material_type) :: mat, apex_mat
        real(wp), parameter :: phi = 30.0_wp*deg, psi = 10.0_wp*deg, tcut = 5.0e3_wp
        real(wp) :: alpha, k, apsi, s(6), s0(6), st(2), tr(6), de(6), tol, rho_c, sdev(6)
        real(wp) :: tdev(6)

        call new_material(mat, make_spec(phi, coh, psi, cone_plane_strain, &
            tension_cutoff=tcut))
        call drucker_prager_cone(cone_plane_strain, phi, coh, psi, alpha, k, apsi)
        call check(suite, tcut < k/alpha, "returns: cut-off below the apex")

        ! cone, from an isotropic state, by a general strain increment
        de = [-1.0e-2_wp, 5.0e-3_wp, 2.0e-3_wp, 4.0e-3_wp, -3.0e-3_wp, 1.0e-3_wp]
        s0 = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        s = s0
        tr = elastic_trial(s, de)
        tol = 100*eps*maxval(abs(tr))
        st = 0.0_wp
        call mat%update_stress(s, de, zero3, 1.0_wp, st)
        call check_plastic_strain(mat, s0, s, de, st, "cone return")
        call check_close(suite, yield(s, alpha, k), 0.0_wp, tol, "cone return: f = 0")
        call check(suite, mean(s) < tcut, "cone return: below the cut-off")
        sdev = deviator(s)
        tdev = deviator(tr)
        call check(suite, maxval(abs(sdev - tdev*radius(s)/radius(tr))) <= tol, &
            "cone return: deviator keeps its direction")
        call check_close(suite, (mean(tr) - mean(s))/mat%bulk, &
            apsi*(radius(tr) - radius(s))/mat%shear, 100*eps*maxval(abs(de)), &
            "cone return: flow rule (m_tr - m)/K = alpha_psi (rho_tr - rho)/G")
        call check(suite, st(1) > 0.0_wp .and. st(2) > 0.0_wp, "cone return: state grows")

        ! tension plane: small shear, large mean tension from a stress-free state
        de = [1.0e-3_wp, 1.0e-3_wp, 1.0e-3_wp, 1.0e-5_wp, 0.0_wp, 0.0_wp]
        s = 0.0_wp
        tr = elastic_trial(s, de)
        tol = 100*eps*maxval(abs(tr))
        st = 0.0_wp
        call mat%update_stress(s, de, zero3, 1.0_wp, st)
        call check_plastic_strain(mat, 0*s, s, de, st, "tension return")
        call check_close(suite, mean(s), tcut, tol, "tension return: m = sigma_t")
        call check(suite, yield(s, alpha, k) < 0.0_wp, "tension return: inside the cone")
        call check(suite, maxval(abs(deviator(s) - deviator(tr))) <= tol, &
            "tension return: deviator unchanged")
        call check_close(suite, st(1), 0.0_wp, 0.0_wp, "tension return: no plastic shear")
        call check_close(suite, st(2), (mean(tr) - tcut)/mat%bulk, 100*eps*maxval(abs(de)), &
            "tension return: plastic volumetric strain (m_tr - sigma_t)/K")

        ! corner of the cone and the cut-off: large shear and large mean tension
        de = [1.0e-3_wp, 1.0e-3_wp, 1.0e-3_wp, 2.0e-3_wp, 0.0_wp, 0.0_wp]
        s = 0.0_wp
        tr = elastic_trial(s, de)
        tol = 100*eps*maxval(abs(tr))
        st = 0.0_wp
        call mat%update_stress(s, de, zero3, 1.0_wp, st)
        call check_plastic_strain(mat, 0*s, s, de, st, "corner return")
        rho_c = k - alpha*tcut
        call check_close(suite, mean(s), tcut, tol, "corner return: m = sigma_t")
        call check_close(suite, yield(s, alpha, k), 0.0_wp, tol, "corner return: f = 0")
        call check_close(suite, radius(s), rho_c, tol, "corner return: rho = k - alpha sigma_t")

        ! apex (no cut-off given): tension and shear return to m = k/alpha, s = 0
        call new_material(apex_mat, make_spec(phi, coh, psi, cone_plane_strain))
        s = 0.0_wp
        tr = elastic_trial(s, de)
        tol = 100*eps*maxval(abs(tr))
        st = 0.0_wp
        call apex_mat%update_stress(s, de, zero3, 1.0_wp, st)
        call check_plastic_strain(apex_mat, 0*s, s, de, st, "apex return")
        call check_close(suite, mean(s), k/alpha, tol, "apex return: m = k/alpha")
        call check_close(suite, radius(s), 0.0_wp, tol, "apex return: deviator zero")
        call check_close(suite, yield(s, alpha, k), 0.0_wp, tol, "apex return: f = 0")
        ! 2D: compression and shear return to the cone
        s(1:4) = 0.0_wp
        call apex_mat%update_stress(s(1:4), [-1.0e-3_wp, -1.0e-3_wp, 0.0_wp, 3.0e-3_wp], &
            zero3, 1.0_wp, st)
        call check_close(suite, yield(s(1:4), alpha, k), 0.0_wp, 100*eps*1.0e5_wp, &
            "2D cone return: f = 0")
    end subroutine check_returns

    !> The return map is continuous across the boundaries of its regions (tension plane /
    !> corner, cone / corner). Two sweeps of single steps from zero stress: a fixed mean
    !> tension with a growing shear, and a fixed shear with a mean going from compression to
    !> tension. Neighbouring results may differ by a few times the change of the trial stress
    !> (7.7 Pa and 50 Pa per sweep step; factor 3 allowed); a wrongly chosen region jumps by
    !> a good part of rho_c ~ 6e3 Pa.
    subroutine check_continuity()
        type(drucker_prager_material_type) :: mat
        integer, parameter :: n = 3000
        real(wp) :: s(6), prev(6), st(2), de(6), jump(2), dtrial(2)
        integer :: i, sweep
        logical :: seen_tension, seen_corner, seen_cone, on_plane, on_cone
        real(wp) :: alpha, k, apsi

        call new_material(mat, make_spec(30.0_wp*deg, coh, 10.0_wp*deg, &
            cone_plane_strain, tension_cutoff=5.0e3_wp))
        call drucker_prager_cone(cone_plane_strain, 30.0_wp*deg, coh, 10.0_wp*deg, alpha, k, apsi)
        dtrial = [2*mat%shear*1.0e-6_wp, 3*mat%bulk*2.0e-6_wp]
        seen_tension = .false.
        seen_corner = .false.
        seen_cone = .false.
        jump = 0.0_wp
        do sweep = 1, 2
            do i = 0, n
                if (sweep == 1) then
                    de = [1.0e-3_wp, 1.0e-3_wp, 1.0e-3_wp, i*1.0e-6_wp, 0.0_wp, 0.0_wp]
                else
                    de = -3.0e-3_wp + i*2.0e-6_wp
                    de(4:6) = [2.0e-3_wp, 0.0_wp, 0.0_wp]
                end if
                s = 0.0_wp
                st = 0.0_wp
                call mat%update_stress(s, de, zero3, 1.0_wp, st)
                if (i > 0) jump(sweep) = max(jump(sweep), maxval(abs(s - prev)))
                prev = s
                on_plane = abs(mean(s) - 5.0e3_wp) < 1.0e-9_wp
                on_cone = abs(yield(s, alpha, k)) < 1.0e-9_wp
                seen_tension = seen_tension .or. (on_plane .and. .not. on_cone)
                seen_corner = seen_corner .or. (on_plane .and. on_cone)
                seen_cone = seen_cone .or. (on_cone .and. .not. on_plane)
            end do
        end do
        call check(suite, seen_tension .and. seen_corner .and. seen_cone, &
            "continuity sweeps visit the tension plane, the corner and the cone")
        call check(suite, jump(1) <= 3*dtrial(1), "continuity: tension plane / corner")
        call check(suite, jump(2) <= 3*dtrial(2), "continuity: cone / corner")
    end subroutine check_continuity

    !> Isotropic compression never yields: mean stress = K eps_v after every step, deviator
    !> zero, no plastic strain. Round-off accumulates at most eps |sigma| per step.
    subroutine check_isotropic_compression()
        type(drucker_prager_material_type) :: mat
        real(wp), parameter :: de = -1.0e-3_wp
        integer, parameter :: nstep = 200
        real(wp) :: s(6), st(2)
        integer :: i

        call new_material(mat, make_spec(30.0_wp*deg, 0.0_wp, 0.0_wp, &
            cone_compression))
        s = 0.0_wp
        st = 0.0_wp
        do i = 1, nstep
            call mat%update_stress(s, [de, de, de, 0.0_wp, 0.0_wp, 0.0_wp], zero3, 1.0_wp, st)
        end do
        call check_close(suite, mean(s), mat%bulk*3*de*nstep, &
            10*nstep*eps*abs(mat%bulk*3*de*nstep), "isotropic compression: m = K eps_v")
        call check_close(suite, radius(s), 0.0_wp, 0.0_wp, "isotropic compression: no deviator")
        call check(suite, all(st == 0.0_wp), "isotropic compression: elastic")
    end subroutine check_isotropic_compression

    !> Isotropy of the return: a step in a rotated frame gives the rotated result,
    !> R sigma(sigma0, de) R^T = sigma(R sigma0 R^T, R de R^T), to round-off (100 eps scale),
    !> for a cone return and a corner return.
    subroutine check_frame_invariance()
        type(drucker_prager_material_type) :: mat
        real(wp) :: r(3, 3), s0(6), de(6), a(6), b(6), sta(2), stb(2), scale
        integer :: icase

        call new_material(mat, make_spec(30.0_wp*deg, coh, 10.0_wp*deg, &
            cone_compression, tension_cutoff=5.0e3_wp))
        r = rotation_matrix([1.0_wp, 2.0_wp, -0.5_wp], 0.7_wp)
        do icase = 1, 2
            if (icase == 1) then
                s0 = [-1.2e5_wp, -0.8e5_wp, -1.0e5_wp, 1.0e4_wp, -2.0e4_wp, 5.0e3_wp]
                de = [-1.0e-2_wp, 5.0e-3_wp, 2.0e-3_wp, 4.0e-3_wp, -3.0e-3_wp, 1.0e-3_wp]
            else
                s0 = 0.0_wp
                de = [1.0e-3_wp, 2.0e-3_wp, 1.0e-3_wp, 2.0e-3_wp, 1.0e-3_wp, -1.0e-3_wp]
            end if
            a = s0
            sta = 0.0_wp
            call mat%update_stress(a, de, zero3, 1.0_wp, sta)
            b = rotate(r, s0)
            stb = 0.0_wp
            call mat%update_stress(b, rotate(r, de), zero3, 1.0_wp, stb)
            scale = max(maxval(abs(s0)), 2*mat%shear*maxval(abs(de))*3)
            call check(suite, maxval(abs(rotate(r, a) - b)) <= 100*eps*scale, &
                "frame invariance of the return")
            call check(suite, maxval(abs(sta - stb)) <= 100*eps*maxval(abs(sta)), &
                "frame invariance of the state")
            call check(suite, sta(1) > 0.0_wp, "frame invariance case is plastic")
        end do
    end subroutine check_frame_invariance

    !> A stress on the cone rotated rigidly by theta = pi/2 in N steps (zero strain) must
    !> become R sigma R^T within the forward-Euler error 2 theta^2/N |sigma| (as for the
    !> elastic material) and stay on the cone. Each Euler step grows sqrt(J2) by about
    !> 2 omega^2 rho, which the return removes with d eps_q <= 2 omega^2 rho/(sqrt(3) G):
    !> in all at most 2 theta^2 rho/(sqrt(3) G N).
    subroutine check_rigid_rotation_2d()
        type(drucker_prager_material_type) :: mat
        integer, parameter :: nstep = 20000
        real(wp) :: s(4), st(2), alpha, k, apsi, rho, sx, sy, theta, om, c, sn, tol_rot
        integer :: i

        call new_material(mat, make_spec(30.0_wp*deg, coh, 0.0_wp, &
            cone_plane_strain))
        call drucker_prager_cone(cone_plane_strain, 30.0_wp*deg, coh, 0.0_wp, alpha, k, apsi)
        rho = k + alpha*p0
        sx = -p0 + rho
        sy = -p0 - rho
        s = [sx, sy, -p0, 0.0_wp]
        st = 0.0_wp
        theta = pi/2
        om = -theta/nstep
        do i = 1, nstep
            call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [om, 0.0_wp, 0.0_wp], &
                1.0_wp, st)
        end do
        c = cos(theta)
        sn = sin(theta)
        tol_rot = 2*theta**2/nstep*p0*2
        call check_close(suite, s(1), sx*c*c + sy*sn*sn, tol_rot, "2D rotation on the cone s_xx")
        call check_close(suite, s(2), sx*sn*sn + sy*c*c, tol_rot, "2D rotation on the cone s_yy")
        call check_close(suite, s(4), (sx - sy)*c*sn, tol_rot, "2D rotation on the cone s_xy")
        call check_close(suite, yield(s, alpha, k), 0.0_wp, 100*eps*p0, &
            "2D rotation: stays on the cone")
        call check(suite, st(1) <= 1.01_wp*2*theta**2*rho/(sqrt(3.0_wp)*mat%shear*nstep), &
            "2D rotation: plastic strain only from the Euler error")
    end subroutine check_rigid_rotation_2d

    !> 3D: a general stress inside the cone rotated about an oblique axis: R sigma R^T.
    subroutine check_rigid_rotation_3d()
        type(drucker_prager_material_type) :: mat
        integer, parameter :: nstep = 20000
        real(wp) :: s(6), s0(6), st(2), axis(3), theta, w(3), tol_rot
        integer :: i

        call new_material(mat, make_spec(30.0_wp*deg, coh, 0.0_wp, &
            cone_compression))
        s0 = [-1.2e5_wp, -0.8e5_wp, -1.0e5_wp, 1.0e4_wp, -2.0e4_wp, 5.0e3_wp]
        s = s0
        st = 0.0_wp
        axis = [1.0_wp, 2.0_wp, -0.5_wp]/norm2([1.0_wp, 2.0_wp, -0.5_wp])
        theta = pi/3
        ! rotation by theta about axis: v = w x r, L = skew(w), W_ij = L_ij:
        ! W_xy = -w_z, W_yz = -w_x, W_zx = -w_y
        w = axis*theta/nstep
        do i = 1, nstep
            call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                [-w(3), -w(1), -w(2)], 1.0_wp, st)
        end do
        tol_rot = 2*theta**2/nstep*maxval(abs(s0))*3
        call check(suite, maxval(abs(s - rotate(rotation_matrix(axis, theta), s0))) <= tol_rot, &
            "3D rigid rotation gives R s R^T")
        call check(suite, all(st == 0.0_wp), "3D rigid rotation inside the cone stays elastic")
    end subroutine check_rigid_rotation_3d

    !> phi = 0, c = 0, the apex and a zero increment give finite stresses; phi = 0 (psi = 0)
    !> is a Tresca-like cylinder whose plane-strain shear strength is c; zero increments
    !> leave an elastic stress exactly unchanged.
    subroutine check_degenerate()
        type(drucker_prager_material_type) :: mat
        real(wp) :: s(6), s4(4), st(2), alpha, k, apsi, s0(6)
        integer :: i
        logical :: finite

        ! phi = 0: pure shear reaches tau = c (MC: tau_max = c), no volume change
        call new_material(mat, make_spec(0.0_wp, coh, 0.0_wp, cone_plane_strain))
        s4 = 0.0_wp
        st = 0.0_wp
        do i = 1, 100
            call mat%update_stress(s4, [0.0_wp, 0.0_wp, 0.0_wp, 1.0e-4_wp], zero3, 1.0_wp, st)
        end do
        call check_close(suite, s4(4), coh, 100*eps*coh, "phi = 0: plane-strain tau = c")
        call check(suite, all(s4(1:3) == 0.0_wp), "phi = 0: no normal stress")
        call check(suite, st(2) == 0.0_wp, "phi = 0: no plastic volume change")
        ! phi = 0, no cut-off given: tension is unlimited (cylinder without apex)
        s4 = 0.0_wp
        call mat%update_stress(s4, [1.0e-3_wp, 1.0e-3_wp, 0.0_wp, 0.0_wp], zero3, 1.0_wp, st)
        call check(suite, .not. any(ieee_is_nan(s4)) .and. s4(1) > 0.0_wp, &
            "phi = 0: tension without cut-off is elastic, finite")

        ! c = 0, phi > 0: the apex is the origin
        call new_material(mat, make_spec(30.0_wp*deg, 0.0_wp, 10.0_wp*deg, &
            cone_plane_strain))
        s = 0.0_wp
        st = 0.0_wp
        call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, &
            1.0_wp, st)
        call check(suite, all(s == 0.0_wp) .and. all(st == 0.0_wp), &
            "c = 0: zero stress, zero increment stays zero")
        call mat%update_stress(s, [1.0e-3_wp, 0.0_wp, 2.0e-3_wp, 1.0e-3_wp, 0.0_wp, 0.0_wp], &
            zero3, 1.0_wp, st)
        call check(suite, all(abs(s) <= 100*eps*1.0e5_wp) .and. .not. any(ieee_is_nan(st)), &
            "c = 0: tension returns to the apex (zero stress)")
        s = 0.0_wp
        call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 1.0e-3_wp, 0.0_wp, 0.0_wp], &
            zero3, 1.0_wp, st)
        call check(suite, .not. any(ieee_is_nan(s)) .and. mean(s) <= 0.0_wp, &
            "c = 0: shear from zero stress is finite, not tensile")

        ! phi = 0 and c = 0: no strength at all
        call new_material(mat, make_spec(0.0_wp, 0.0_wp, 0.0_wp, &
            cone_compression))
        s = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        st = 0.0_wp
        call mat%update_stress(s, [-1.0e-3_wp, 2.0e-3_wp, 0.0_wp, 1.0e-3_wp, 0.0_wp, 0.0_wp], &
            [0.01_wp, 0.0_wp, 0.0_wp], 1.0_wp, st)
        finite = .not. (any(ieee_is_nan(s)) .or. any(ieee_is_nan(st)))
        call check(suite, finite .and. radius(s) <= 100*eps*p0, &
            "phi = 0, c = 0: deviator vanishes, finite")

        ! at the apex, zero increment: unchanged, finite
        call new_material(mat, make_spec(30.0_wp*deg, coh, 0.0_wp, &
            cone_compression))
        call drucker_prager_cone(cone_compression, 30.0_wp*deg, coh, 0.0_wp, alpha, k, apsi)
        s = [k/alpha, k/alpha, k/alpha, 0.0_wp, 0.0_wp, 0.0_wp]
        s0 = s
        st = 0.0_wp
        call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, &
            1.0_wp, st)
        call check(suite, maxval(abs(s - s0)) <= 100*eps*k/alpha .and. &
            .not. any(ieee_is_nan(s)), "apex, zero increment: unchanged, finite")
        ! elastic state, zero increment: exactly unchanged
        s = [-1.2e5_wp, -0.8e5_wp, -1.0e5_wp, 1.0e4_wp, -2.0e4_wp, 5.0e3_wp]
        s0 = s
        call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, &
            1.0_wp, st)
        call check(suite, all(s == s0), "zero increment: elastic stress unchanged")
    end subroutine check_degenerate

    !> Softening in triaxial compression (compression cone): the peak is the MC strength of
    !> the peak values (first yield uses them), the end the MC strength of the residual values.
    !> Every step uses the strength of the state at the start of the step, so after each plastic
    !> step q is the MC strength of phi(eps_prev), c(eps_prev) (eps_prev = eps_q^p before it),
    !> the values of the softening law: linear, x_p + (x_r - x_p) min(eps/eps_s, 1), or
    !> exponential, x_r + (x_p - x_r) exp(-eps/eps_s).
    subroutine check_softening(law)
        integer, intent(in) :: law
            !! softening law

        type(drucker_prager_material_type) :: mat
        type(material_spec_type) :: spec
        real(wp), parameter :: de = -5.0e-4_wp
        integer, parameter :: nstep = 2000
        real(wp) :: s(6), st(2), x, q, qmax, eprev, phi, c, gap
        logical :: ok
        integer :: i
        character(len=:), allocatable :: tag

        tag = merge("linear softening:     ", "exponential softening:", law == softening_linear)
        spec = make_spec(35.0_wp*deg, 2.0e4_wp, 5.0_wp*deg, cone_compression)
        spec%strength%softening = law
        spec%strength%friction_residual = 25.0_wp*deg
        spec%strength%cohesion_residual = 0.0_wp
        spec%strength%dilatancy_residual = 0.0_wp
        spec%strength%softening_strain = merge(0.05_wp, 0.02_wp, law == softening_linear)
        call new_material(mat, spec)
        call check(suite, mat%nstate() == 2, tag//" nstate = 2")
        s = [-p0, -p0, -p0, 0.0_wp, 0.0_wp, 0.0_wp]
        st = 0.0_wp
        x = 0.0_wp
        ok = .true.
        qmax = 0.0_wp
        eprev = 0.0_wp
        gap = 0.0_wp
        do i = 1, nstep
            eprev = st(1)
            call mixed_step(mat, s, st, [0.0_wp, de, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                [.true., .false., .true., .false., .false., .false.], -p0, x, ok)
            q = s(1) - s(2)
            qmax = max(qmax, q)
            if (st(1) > eprev) then
                phi = soft(law, spec%strength%friction, spec%strength%friction_residual, eprev, &
                    spec%strength%softening_strain)
                c = soft(law, spec%strength%cohesion, spec%strength%cohesion_residual, eprev, &
                    spec%strength%softening_strain)
                gap = max(gap, abs(q - q_compression(phi, c)))
            end if
        end do
        call check(suite, ok, tag//" mixed control converged")
        call check_close(suite, qmax, q_compression(spec%strength%friction, spec%strength%cohesion), 40*tol_mixed, &
            tag//" peak q = MC peak strength")
        call check_close(suite, gap, 0.0_wp, 40*tol_mixed, &
            tag//" every plastic step: q = MC strength of the start-of-step eps_q")
        ! linear: residual from eps_s on; exponential: the distance to the residual strength,
        ! (q_peak - q_res) exp(-eps_q/eta) < 2e5 exp(-30) ~ 2e-8 Pa once eps_q > 30 eta, is
        ! far below the mixed-control tolerance
        call check(suite, st(1) > merge(1, 30, law == softening_linear)*spec%strength%softening_strain, &
            tag//" softening strain passed")
        call check_close(suite, q, q_compression(spec%strength%friction_residual, &
            spec%strength%cohesion_residual), 40*tol_mixed, tag//" residual strength")
        call check(suite, .not. (ieee_is_nan(q) .or. any(ieee_is_nan(st))), tag//" finite")
    end subroutine check_softening

    !> Softening law, written out independently of the module.
    pure real(wp) function soft(law, peak, residual, eps_q, eps_s)
        integer, intent(in) :: law
        real(wp), intent(in) :: peak, residual, eps_q, eps_s
        if (law == softening_linear) then
            soft = peak + (residual - peak)*min(eps_q/eps_s, 1.0_wp)
        else
            soft = residual + (peak - residual)*exp(-eps_q/eps_s)
        end if
    end function soft

    !> The state after one step from zero state equals the plastic strain of the step,
    !> total minus elastic: eps_v^p = tr(de) - dm/K, e^p = dev(de) - dev(ds)/(2G),
    !> eps_q^p = sqrt(2/3 e^p : e^p). Round-off: 100 eps |de|.
    subroutine check_plastic_strain(mat, s0, s1, de, st, what)
        type(drucker_prager_material_type), intent(in) :: mat
        real(wp), intent(in) :: s0(:), s1(:), de(:), st(2)
        character(len=*), intent(in) :: what

        real(wp) :: ep(size(de)), tol

        tol = 100*eps*maxval(abs(de))
        ep = deviator(de) - deviator(s1 - s0)/(2*mat%shear)
        call check_close(suite, st(1), sqrt(2.0_wp/3*(sum(ep(1:3)**2) + 2*sum(ep(4:)**2))), tol, &
            what//": state(1) = eps_q^p of the step")
        call check_close(suite, st(2), sum(de(1:3)) - (mean(s1) - mean(s0))/mat%bulk, tol, &
            what//": state(2) = eps_v^p of the step")
    end subroutine check_plastic_strain

    !> Triaxial compression strength at cell pressure p0 (MC compression meridian) [Pa].
    pure real(wp) function q_compression(phi, c)
        real(wp), intent(in) :: phi, c
        q_compression = 2*(c*cos(phi) + p0*sin(phi))/(1 - sin(phi))
    end function q_compression

    !> One step with mixed control: the strain components flagged `unknown` all take the
    !> value x, found by the secant method so that stress(1) = target to tol_mixed.
    subroutine mixed_step(mat, s, st, de, unknown, target, x, ok)
        type(drucker_prager_material_type), intent(in) :: mat
        real(wp), intent(inout) :: s(:), st(:)
        real(wp), intent(in) :: de(:)
        logical, intent(in) :: unknown(:)
        real(wp), intent(in) :: target
        real(wp), intent(inout) :: x
            !! guess in (the previous step's value), solution out
        logical, intent(inout) :: ok
            !! set to false when the secant method does not converge

        real(wp) :: x0, x1, r0, r1, xn, stiff
        integer :: it

        stiff = count(unknown(1:3))*mat%lame + 2*mat%shear
        x0 = x
        r0 = mixed_residual(mat, s, st, de, unknown, target, x0)
        x1 = x0 - r0/stiff
        r1 = mixed_residual(mat, s, st, de, unknown, target, x1)
        do it = 1, 100
            if (abs(r1) <= tol_mixed .or. r1 == r0) exit
            xn = x1 - r1*(x1 - x0)/(r1 - r0)
            x0 = x1
            r0 = r1
            x1 = xn
            r1 = mixed_residual(mat, s, st, de, unknown, target, x1)
        end do
        ok = ok .and. abs(r1) <= tol_mixed
        x = x1
        call mat%update_stress(s, merge(x1, de, unknown), zero3, 1.0_wp, st)
    end subroutine mixed_step

    !> stress(1) - target after a trial update with the unknown components set to x.
    real(wp) function mixed_residual(mat, s, st, de, unknown, target, x) result(r)
        type(drucker_prager_material_type), intent(in) :: mat
        real(wp), intent(in) :: s(:), st(:), de(:)
        logical, intent(in) :: unknown(:)
        real(wp), intent(in) :: target, x

        real(wp) :: sc(size(s)), stc(size(st))

        sc = s
        stc = st
        call mat%update_stress(sc, merge(x, de, unknown), zero3, 1.0_wp, stc)
        r = sc(1) - target
    end function mixed_residual

    !> The block update (update_stress_block: predictor and return without a branch per
    !> particle, vectorised) against update_stress one particle at a time, in 3D and 2D, for
    !> 75 particles (chunks of 32 and a remainder) and four strengths (cut-off below the apex,
    !> the cylinder without one, the apex of a cohesionless compression cone, an extension cone
    !> with dilatancy): random stresses about the surface and random strain increments and
    !> spins, some particles at rest with zero stress; a second round from the returned
    !> stresses with increments of 1e-9 (just outside the surface or just inside). The same
    !> operations in the same order: they agree to 100 eps of the trial stress (FMA contraction
    !> may differ), the state to that over G; plastic and elastic particles in every round.
    subroutine check_block_update()
        integer, parameter :: n = 75
        type(drucker_prager_material_type) :: mat
        type(material_spec_type) :: specs(4)
        real(wp) :: s(6, n), sb(6, n), s0(6, n), de(6, n), om(3, n), st(2, n), stb(2, n)
        real(wp) :: st0(2, n), pt(6), scale, diff, shear
        integer :: imat, ndim, ns, j, i, nplastic, nelastic, nbad, round
        integer :: seed
        character(len=60) :: label

        specs(1) = make_spec(30.0_wp*deg, coh, 10.0_wp*deg, cone_plane_strain, &
            tension_cutoff=5.0e3_wp)
        specs(2) = make_spec(0.0_wp, 2.0_wp*coh, 0.0_wp, cone_plane_strain)
        specs(3) = make_spec(35.0_wp*deg, 0.0_wp, 0.0_wp, cone_compression)
        specs(4) = make_spec(20.0_wp*deg, 0.5_wp*coh, 20.0_wp*deg, cone_extension, &
            tension_cutoff=2.0e3_wp)
        shear = young/(2.0_wp*(1.0_wp + poisson))
        seed = 4242
        do imat = 1, size(specs)
            call new_material(mat, specs(imat))
            do ndim = 2, 3
                ns = merge(6, 4, ndim == 3)
                do j = 1, n
                    pt(1:3) = 2.0e5_wp*uniform(seed) - 1.8e5_wp + 4.0e4_wp*(2*[uniform(seed), &
                        uniform(seed), uniform(seed)] - 1)
                    pt(4:6) = 0.0_wp
                    s(:, j) = rotate(rotation_matrix([uniform(seed), uniform(seed), &
                        uniform(seed)] - 0.5_wp, 7*uniform(seed)), pt)
                    if (ndim == 2) s(:, j) = rotate(rotation_matrix([0.0_wp, 0.0_wp, 1.0_wp], &
                        7*uniform(seed)), pt)
                    do i = 1, 6
                        de(i, j) = 4.0e-3_wp*(2*uniform(seed) - 1)
                    end do
                    do i = 1, 3
                        om(i, j) = 1.0e-2_wp*(2*uniform(seed) - 1)
                    end do
                    if (ndim == 2) then
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
                        do j = 1, n
                            do i = 1, 6
                                de(i, j) = 1.0e-9_wp*(2*uniform(seed) - 1)
                            end do
                            if (ndim == 2) de(3, j) = 0.0_wp
                            if (mod(j, 11) == 0) de(:, j) = 0.0_wp
                        end do
                        om = 0.0_wp
                    end if
                    st0 = st
                    sb = s
                    s0 = s
                    stb = st
                    do j = 1, n
                        call mat%update_stress(s(1:ns, j), de(1:ns, j), om(:, j), 1.0_wp, &
                            st(:, j))
                    end do
                    call mat%update_stress_block(n, sb(1:ns, :), de(1:ns, :), om, 1.0_wp, stb)
                    nbad = 0
                    nplastic = count(st(2, :) /= st0(2, :) .or. st(1, :) /= st0(1, :))
                    nelastic = n - nplastic
                    do j = 1, n
                        scale = max(maxval(abs(s0(1:ns, j))), young*maxval(abs(de(1:ns, j))), &
                            1.0_wp)
                        diff = max(maxval(abs(sb(1:ns, j) - s(1:ns, j))), &
                            shear*maxval(abs(stb(:, j) - st(:, j))))
                        if (.not. diff <= 100*eps*scale) nbad = nbad + 1
                        if (mod(j, 11) == 0 .and. any(sb(1:ns, j) /= 0.0_wp)) nbad = nbad + 1
                    end do
                    write (label, "(a,i0,a,i0,a,i0)") "block update, material ", imat, ", ", &
                        ndim, "D, round ", round
                    call check(suite, nbad == 0, trim(label)//": as particle by particle")
                    call check(suite, nplastic > 5 .and. nelastic > 5, &
                        trim(label)//": plastic and elastic particles")
                end do
            end do
        end do
    end subroutine check_block_update

    !> Uniform number in (0, 1) of a fixed linear congruential sequence (Park-Miller).
    real(wp) function uniform(seed)
        integer, intent(inout) :: seed
        integer(kind=8), parameter :: mult = 16807, modulus = 2147483647
        seed = int(mod(mult*int(seed, 8), modulus))
        uniform = real(seed, wp)/real(modulus, wp)
    end function uniform

    !> A Drucker-Prager material of E, nu of this test, rho = 2000 kg/m3 and `spec`.
    subroutine new_material(mat, spec)
        type(drucker_prager_material_type), intent(out) :: mat
        type(material_spec_type), intent(in) :: spec
        call new_drucker_prager_material(mat, young, poisson, 2000.0_wp, spec%strength, spec%cone)
    end subroutine new_material

    !> Material specification with E, nu of this test.
    function make_spec(phi, c, psi, cone, tension_cutoff) result(spec)
        real(wp), intent(in) :: phi, c, psi
        integer, intent(in) :: cone
        real(wp), intent(in), optional :: tension_cutoff
        type(material_spec_type) :: spec

        spec%strength%friction = phi
        spec%strength%cohesion = c
        spec%strength%dilatancy = psi
        spec%cone = cone
        spec%strength%softening = softening_none
        if (present(tension_cutoff)) spec%strength%tension_cutoff = tension_cutoff
    end function make_spec

    !> Elastic trial stress (no rotation), computed here independently of the module.
    pure function elastic_trial(s, de) result(t)
        real(wp), intent(in) :: s(:), de(:)
        real(wp) :: t(size(s))
        real(wp) :: lame, g
        g = young/(2*(1 + poisson))
        lame = young*poisson/((1 + poisson)*(1 - 2*poisson))
        t = s + 2*g*de
        t(1:3) = t(1:3) + lame*sum(de(1:3))
    end function elastic_trial

    !> Elastic strain of the normal stresses (isotropic Hooke) [-].
    pure function compliance(sig) result(e)
        real(wp), intent(in) :: sig(3)
        real(wp) :: e(3)
        e = ((1 + poisson)*sig - poisson*sum(sig))/young
    end function compliance

    pure real(wp) function mean(s)
        real(wp), intent(in) :: s(:)
        mean = sum(s(1:3))/3
    end function mean

    pure function deviator(s) result(d)
        real(wp), intent(in) :: s(:)
        real(wp) :: d(size(s))
        d = s
        d(1:3) = d(1:3) - mean(s)
    end function deviator

    !> sqrt(J2) [Pa].
    pure real(wp) function radius(s)
        real(wp), intent(in) :: s(:)
        real(wp) :: d(size(s))
        d = deviator(s)
        radius = sqrt(0.5_wp*sum(d(1:3)**2) + sum(d(4:)**2))
    end function radius

    !> f = sqrt(J2) + alpha m - k [Pa].
    pure real(wp) function yield(s, alpha, k)
        real(wp), intent(in) :: s(:), alpha, k
        yield = radius(s) + alpha*mean(s) - k
    end function yield

    pure function rotation_matrix(axis, theta) result(r)
        real(wp), intent(in) :: axis(3), theta
        real(wp) :: r(3, 3), n(3), kx(3, 3)
        integer :: i
        n = axis/norm2(axis)
        kx = reshape([0.0_wp, n(3), -n(2), -n(3), 0.0_wp, n(1), n(2), -n(1), 0.0_wp], [3, 3])
        r = sin(theta)*kx + (1 - cos(theta))*matmul(kx, kx)
        do i = 1, 3
            r(i, i) = r(i, i) + 1
        end do
    end function rotation_matrix

    !> R t R^T for a symmetric tensor in Voigt storage (6 components).
    pure function rotate(r, t) result(u)
        real(wp), intent(in) :: r(3, 3), t(6)
        real(wp) :: u(6), a(3, 3)
        a = reshape([t(1), t(4), t(6), t(4), t(2), t(5), t(6), t(5), t(3)], [3, 3])
        a = matmul(r, matmul(a, transpose(r)))
        u = [a(1, 1), a(2, 2), a(3, 3), a(1, 2), a(2, 3), a(3, 1)]
    end function rotate

end program test_mpm_material_drucker_prager
