!> Linear elastic material: Hooke's law for uniaxial strain, shear and isotropic compression,
!> and objectivity of the Jaumann update under a rigid rotation (2D and 3D).
program test_mpm_material_elastic
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_material_elastic, only: elastic_material_type, new_elastic_material
    use mpm_stress, only: jaumann_rotation
    implicit none

    type(test_suite_type) :: suite
    type(elastic_material_type) :: mat
    real(wp), parameter :: young = 1.0e7_wp, poisson = 0.3_wp
    real(wp) :: lame, shear, s6(6), s4(4), nostate(0)
    real(wp), parameter :: eps = 1.0e-4_wp
    real(wp), parameter :: tol = 100.0_wp*epsilon(1.0_wp)*young*eps

    call new_suite(suite, "mpm_material_elastic")
    call new_elastic_material(mat, "rock", young, poisson, 2000.0_wp)
    lame = young*poisson/((1 + poisson)*(1 - 2*poisson))
    shear = young/(2*(1 + poisson))

    ! uniaxial strain (oedometric): s_xx = (lambda + 2G) e, s_yy = s_zz = lambda e
    s6 = 0.0_wp
    call mat%update_stress(s6, [eps, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp, nostate)
    call check_close(suite, s6(1), (lame + 2*shear)*eps, tol, "3D uniaxial strain s_xx")
    call check_close(suite, s6(2), lame*eps, tol, "3D uniaxial strain s_yy")
    call check_close(suite, s6(3), lame*eps, tol, "3D uniaxial strain s_zz")
    ! simple shear: s_xy = 2 G e_xy, no normal stress
    s4 = 0.0_wp
    call mat%update_stress(s4, [0.0_wp, 0.0_wp, 0.0_wp, eps], [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp, nostate)
    call check_close(suite, s4(4), 2*shear*eps, tol, "2D shear s_xy = 2 G e_xy")
    call check_close(suite, s4(1), 0.0_wp, tol, "2D shear gives no s_xx")
    ! isotropic compression: p = -K e_vol
    s6 = 0.0_wp
    call mat%update_stress(s6, [-eps, -eps, -eps, 0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp, nostate)
    call check_close(suite, sum(s6(1:3))/3, -young/(3*(1 - 2*poisson))*3*eps, tol, &
        "isotropic compression: mean stress = K e_vol")
    ! plane strain uniaxial strain in 2D: s_zz = lambda e (out-of-plane stress)
    s4 = 0.0_wp
    call mat%update_stress(s4, [eps, 0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp, nostate)
    call check_close(suite, s4(3), lame*eps, tol, "2D plane strain s_zz = lambda e_xx")

    call check_rotation_2d()
    call check_rotation_3d()
    call finish(suite)

contains

    !> A stress s0 = diag(s, 0) rotated rigidly by theta in N steps must become R s0 R^T.
    !> Forward-Euler integration of the Jaumann rate rotates with relative error of order
    !> theta * (theta / N); with theta = pi/2 and N = 20000 that is about 1.2e-4.
    subroutine check_rotation_2d()
        real(wp) :: s(4), theta, omega, c, sn
        integer :: k
        integer, parameter :: nstep = 20000
        real(wp), parameter :: s0 = -1.0e5_wp
        real(wp) :: tol_rot

        theta = acos(-1.0_wp)/2
        ! counter-clockwise rotation: L = [[0, -w], [w, 0]], W_xy = -w
        omega = -theta/nstep
        s = [s0, 0.0_wp, 0.0_wp, 0.0_wp]
        do k = 1, nstep
            call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], [omega, 0.0_wp, 0.0_wp], 1.0_wp, nostate)
        end do
        c = cos(theta)
        sn = sin(theta)
        tol_rot = 2.0_wp*theta**2/nstep*abs(s0)
        call check_close(suite, s(1), s0*c*c, tol_rot, "2D rigid rotation s_xx")
        call check_close(suite, s(2), s0*sn*sn, tol_rot, "2D rigid rotation s_yy")
        call check_close(suite, s(4), s0*c*sn, tol_rot, "2D rigid rotation s_xy")
        call check_close(suite, s(1) + s(2), s0, 100*epsilon(1.0_wp)*abs(s0)*nstep, &
            "2D rigid rotation keeps the trace")
    end subroutine check_rotation_2d

    !> 3D: rotate a general stress about the x axis by theta and compare with R s R^T.
    subroutine check_rotation_3d()
        real(wp) :: s(6), theta, om, r(3, 3), a(3, 3), b(3, 3), dsig(6)
        integer :: k
        integer, parameter :: nstep = 20000
        real(wp) :: tol_rot

        theta = acos(-1.0_wp)/3
        om = theta/nstep
        s = [-3.0e5_wp, -2.0e5_wp, -1.0e5_wp, 4.0e4_wp, 2.0e4_wp, -1.0e4_wp]
        a = voigt_to_matrix(s)
        ! rotation about x by +theta: v = w x r, L = [[0,0,0],[0,0,-w],[0,w,0]], W_yz = -w
        do k = 1, nstep
            call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                [0.0_wp, -om, 0.0_wp], 1.0_wp, nostate)
        end do
        r = reshape([1.0_wp, 0.0_wp, 0.0_wp, 0.0_wp, cos(theta), sin(theta), &
            0.0_wp, -sin(theta), cos(theta)], [3, 3])
        b = matmul(r, matmul(a, transpose(r)))
        tol_rot = 2.0_wp*theta**2/nstep*maxval(abs(a))*3
        call check(suite, maxval(abs(voigt_to_matrix(s) - b)) <= tol_rot, &
            "3D rigid rotation about x gives R s R^T")
        dsig = jaumann_rotation([1.0_wp, 2.0_wp, 3.0_wp, 0.4_wp, 0.5_wp, 0.6_wp], &
            [0.01_wp, -0.02_wp, 0.03_wp])
        call check_close(suite, dsig(1) + dsig(2) + dsig(3), 0.0_wp, 100*epsilon(1.0_wp), &
            "Jaumann rotation leaves the trace unchanged")
    end subroutine check_rotation_3d

    pure function voigt_to_matrix(s) result(m)
        real(wp), intent(in) :: s(6)
        real(wp) :: m(3, 3)
        m = reshape([s(1), s(4), s(6), s(4), s(2), s(5), s(6), s(5), s(3)], [3, 3])
    end function voigt_to_matrix

end program test_mpm_material_elastic
