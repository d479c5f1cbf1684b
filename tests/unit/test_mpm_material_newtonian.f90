!> Newtonian fluid: viscous shear stress, pressure from the volume change in rate form,
!> inviscid limit, plane strain (2D) and 3D, no accumulation of the viscous stress, and
!> the rotation invariance that replaces the Jaumann term.
program test_mpm_material_newtonian
    use, intrinsic :: ieee_arithmetic, only: ieee_is_nan
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_material_newtonian, only: newtonian_material_type, new_newtonian_material
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: mu = 1.0e-3_wp       ! water-like viscosity [Pa s]
    real(wp), parameter :: bulk = 2.0e6_wp      ! weakly compressible bulk modulus [Pa]
    real(wp), parameter :: dt = 1.0e-4_wp       ! time step [s]
    real(wp), parameter :: rate = 50.0_wp       ! shear rate gamma_dot [1/s]
    real(wp), parameter :: eps = epsilon(1.0_wp)
    real(wp), parameter :: zero3(3) = 0.0_wp

    type(newtonian_material_type) :: fluid, inviscid
    real(wp) :: nostate(0)

    call new_suite(suite, "mpm_material_newtonian")
    call new_newtonian_material(fluid, "water", mu, bulk, 1000.0_wp)
    call new_newtonian_material(inviscid, "water", 0.0_wp, bulk, 1000.0_wp)
    call check(suite, fluid%nstate() == 0, "no state variables")
    call check_close(suite, fluid%density, 1000.0_wp, 0.0_wp, "density as given")
    call check_shear()
    call check_isotropic_compression()
    call check_uniaxial()
    call check_inviscid()
    call check_rotation()
    call check_zero_dt()
    call finish(suite)

contains

    !> Simple shear at rate gamma_dot: D_xy = gamma_dot/2, tau = 2 mu D_xy = mu gamma_dot,
    !> no normal stress, and the same tau after many steps (the viscous stress is not
    !> accumulated). One product and a division: tol 10 eps tau.
    subroutine check_shear()
        real(wp) :: s4(4), s6(6), tau
        integer :: i

        tau = mu*rate
        s4 = 0.0_wp
        do i = 1, 10
            call fluid%update_stress(s4, [0.0_wp, 0.0_wp, 0.0_wp, rate*dt/2], zero3, dt, nostate)
        end do
        call check_close(suite, s4(4), tau, 10*eps*tau, "2D simple shear: tau = mu gamma_dot")
        call check(suite, all(s4(1:3) == 0.0_wp), "2D simple shear: no normal stress")
        s6 = 0.0_wp
        do i = 1, 10
            call fluid%update_stress(s6, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, rate*dt/2, 0.0_wp], &
                zero3, dt, nostate)
        end do
        call check_close(suite, s6(5), tau, 10*eps*tau, "3D simple shear (yz): tau = mu gamma_dot")
        call check(suite, all(s6([1, 2, 3, 4, 6]) == 0.0_wp), "3D simple shear: other stresses 0")
    end subroutine check_shear

    !> Isotropic compression by eps_v per step over n steps: p = -K sum(eps_v) (compression
    !> positive), no deviatoric stress. 3D: de_xx = de_yy = de_zz; 2D: de_xx = de_yy, de_zz = 0,
    !> which has a deviatoric rate, so sigma_xx = -p + 2 mu (D_xx - tr D/3),
    !> sigma_zz = -p + 2 mu (0 - tr D/3). Round-off grows by about eps p per step: tol 10 n eps p.
    subroutine check_isotropic_compression()
        real(wp), parameter :: de = -1.0e-5_wp
        integer, parameter :: n = 100
        real(wp) :: s6(6), s4(4), p, trd
        integer :: i

        s6 = 0.0_wp
        do i = 1, n
            call fluid%update_stress(s6, [de, de, de, 0.0_wp, 0.0_wp, 0.0_wp], zero3, dt, nostate)
        end do
        p = -bulk*3*de*n
        call check_close(suite, -sum(s6(1:3))/3, p, 10*n*eps*p, "3D compression: p = K eps_v")
        call check(suite, maxval(abs(s6(1:3) - s6(1))) <= 10*n*eps*p .and. all(s6(4:6) == 0), &
            "3D compression: isotropic stress")

        s4 = 0.0_wp
        do i = 1, n
            call fluid%update_stress(s4, [de, de, 0.0_wp, 0.0_wp], zero3, dt, nostate)
        end do
        p = -bulk*2*de*n
        trd = 2*de/dt
        call check_close(suite, -sum(s4(1:3))/3, p, 10*n*eps*p, "2D compression: p = K eps_v")
        call check_close(suite, s4(1), -p + 2*mu*(de/dt - trd/3), 10*n*eps*p, &
            "2D compression: sigma_xx = -p + 2 mu (D_xx - tr D/3)")
        call check_close(suite, s4(3), -p + 2*mu*(0.0_wp - trd/3), 10*n*eps*p, &
            "2D compression: sigma_zz = -p + 2 mu (0 - tr D/3)")
    end subroutine check_isotropic_compression

    !> 3D uniaxial compression in one step: p = -K de, sigma_yy = -p + 2 mu (D_yy - tr D/3),
    !> sigma_xx = -p + 2 mu (0 - tr D/3).
    subroutine check_uniaxial()
        real(wp), parameter :: de = -1.0e-4_wp
        real(wp) :: s6(6), p, trd

        s6 = 0.0_wp
        call fluid%update_stress(s6, [0.0_wp, de, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, dt, &
            nostate)
        p = -bulk*de
        trd = de/dt
        call check_close(suite, s6(2), -p + 2*mu*(trd - trd/3), 10*eps*p, "3D uniaxial sigma_yy")
        call check_close(suite, s6(1), -p + 2*mu*(-trd/3), 10*eps*p, "3D uniaxial sigma_xx")
        call check_close(suite, s6(3), s6(1), 10*eps*p, "3D uniaxial sigma_zz = sigma_xx")
    end subroutine check_uniaxial

    !> mu = 0: no shear stress at any rate, the pressure alone.
    subroutine check_inviscid()
        real(wp) :: s4(4), s6(6)

        s4 = [-1.0e3_wp, -1.0e3_wp, -1.0e3_wp, 0.0_wp]
        call inviscid%update_stress(s4, [1.0e-3_wp, -2.0e-3_wp, 0.0_wp, 5.0e-3_wp], zero3, dt, &
            nostate)
        call check(suite, s4(4) == 0.0_wp, "2D inviscid: no shear stress")
        ! p_n = 1e3, tr(de) = -1e-3: p = 1e3 + K 1e-3
        call check_close(suite, s4(1), -(1.0e3_wp + bulk*1.0e-3_wp), 10*eps*bulk*1.0e-3_wp, &
            "2D inviscid: sigma = -p I, p = p_n - K tr(de)")
        call check(suite, s4(1) == s4(2) .and. s4(2) == s4(3), "2D inviscid: isotropic")
        s6 = 0.0_wp
        call inviscid%update_stress(s6, [0.0_wp, 0.0_wp, 0.0_wp, 1.0e-3_wp, 2.0e-3_wp, &
            3.0e-3_wp], zero3, dt, nostate)
        call check(suite, all(s6 == 0.0_wp), "3D inviscid: pure shear gives no stress")
    end subroutine check_inviscid

    !> A spin alone (no strain) keeps the pressure and drops the viscous stress of the previous
    !> step: the viscous part is a function of the current D only, and -p I is isotropic, so
    !> a rigid rotation creates no stress (2D and 3D).
    subroutine check_rotation()
        real(wp) :: s4(4), s6(6)

        s4 = 0.0_wp
        call fluid%update_stress(s4, [-1.0e-4_wp, 0.0_wp, 0.0_wp, rate*dt/2], zero3, dt, nostate)
        call fluid%update_stress(s4, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [0.3_wp, 0.0_wp, 0.0_wp], &
            dt, nostate)
        call check(suite, s4(4) == 0.0_wp .and. s4(1) == s4(2) .and. s4(2) == s4(3), &
            "2D rotation: isotropic pressure only")
        call check_close(suite, s4(1), bulk*(-1.0e-4_wp), 10*eps*bulk*1.0e-4_wp, &
            "2D rotation: pressure kept")
        s6 = [-5.0e2_wp, -5.0e2_wp, -5.0e2_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        call fluid%update_stress(s6, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
            [0.1_wp, -0.2_wp, 0.3_wp], dt, nostate)
        call check(suite, all(s6(1:3) == -5.0e2_wp) .and. all(s6(4:6) == 0.0_wp), &
            "3D rotation: pressure unchanged")
    end subroutine check_rotation

    !> dt <= 0 (guarded although the solver never passes it): pressure only, finite.
    subroutine check_zero_dt()
        real(wp) :: s4(4)

        s4 = 0.0_wp
        call fluid%update_stress(s4, [-1.0e-4_wp, 0.0_wp, 0.0_wp, 1.0e-4_wp], zero3, 0.0_wp, &
            nostate)
        call check(suite, .not. any(ieee_is_nan(s4)) .and. s4(4) == 0.0_wp, &
            "dt = 0: finite, no viscous stress")
        call check_close(suite, s4(1), -bulk*1.0e-4_wp, 10*eps*bulk*1.0e-4_wp, &
            "dt = 0: pressure still updated")
    end subroutine check_zero_dt

end program test_mpm_material_newtonian
