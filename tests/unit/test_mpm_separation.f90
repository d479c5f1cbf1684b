!> Separation of cohesionless Mohr-Coulomb and Drucker-Prager materials (`mpm_separation`):
!> an isotropic extension from zero stress opens the material by exactly its volume change,
!> shear while open leaves it stress free and counts as plastic shear, compression first
!> closes the opening with no stress and then loads with the bulk modulus; without separation
!> the same path builds the stress at once. 2D (plane strain, 4 components) and 3D.
program test_mpm_separation
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_softening, only: softening_none
    use mpm_strength, only: strength_type
    use mpm_material, only: material_type
    use mpm_material_mohr_coulomb, only: mohr_coulomb_material_type, new_mohr_coulomb_material
    use mpm_material_drucker_prager, only: drucker_prager_material_type, &
        new_drucker_prager_material, cone_plane_strain
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: young = 1.0e6_wp, poisson = 0.3_wp
    real(wp), parameter :: bulk = young/(3.0_wp*(1.0_wp - 2.0_wp*poisson))
    real(wp), parameter :: e0 = 1.0e-3_wp   ! strain of each step [-]
    real(wp), parameter :: zero3(3) = 0.0_wp
    type(mohr_coulomb_material_type) :: mc
    type(drucker_prager_material_type) :: dp
    integer :: ns

    call new_suite(suite, "mpm_separation")
    do ns = 4, 6, 2
        call new_mohr_coulomb_material(mc, young, poisson, 1800.0_wp, sand(.true.))
        call check_cycle(mc, "mohr_coulomb", ns)
        call new_drucker_prager_material(dp, young, poisson, 1800.0_wp, sand(.true.), &
            cone_plane_strain)
        call check_cycle(dp, "drucker_prager", ns)
        call new_mohr_coulomb_material(mc, young, poisson, 1800.0_wp, sand(.false.))
        call check_without(mc, "mohr_coulomb", ns)
        call new_drucker_prager_material(dp, young, poisson, 1800.0_wp, sand(.false.), &
            cone_plane_strain)
        call check_without(dp, "drucker_prager", ns)
    end do
    call new_mohr_coulomb_material(mc, young, poisson, 1800.0_wp, sand(.true.))
    call check(suite, mc%nstate() == 3, "mohr_coulomb: three state values with separation")
    call new_mohr_coulomb_material(mc, young, poisson, 1800.0_wp, sand(.false.))
    call check(suite, mc%nstate() == 2, "mohr_coulomb: two state values without")
    call finish(suite)

contains

    !> phi = 30 deg, c = 0, psi = 0 (with E = 1 MPa, nu = 0.3).
    type(strength_type) function sand(separation)
        logical, intent(in) :: separation
        sand%friction = 30.0_wp*acos(-1.0_wp)/180.0_wp
        sand%cohesion = 0.0_wp
        sand%dilatancy = 0.0_wp
        sand%softening = softening_none
        sand%separation = separation
    end function sand

    !> Isotropic strain increment of trace 3 e (normal components e, shear 0).
    function isotropic(e, n) result(de)
        real(wp), intent(in) :: e
        integer, intent(in) :: n
        real(wp) :: de(n)
        de = 0.0_wp
        de(1:3) = e
    end function isotropic

    subroutine check_cycle(mat, name, n)
        class(material_type), intent(in) :: mat
        character(len=*), intent(in) :: name
        integer, intent(in) :: n
        real(wp) :: stress(n), state(3), de(n), tol
        character(len=:), allocatable :: label

        label = name//merge(" 2D", " 3D", n == 4)//": "
        tol = 10.0_wp*epsilon(1.0_wp)
        stress = 0.0_wp
        state = 0.0_wp
        ! pulled apart from zero stress: all of it opens
        call mat%update_stress(stress, isotropic(e0, n), zero3, 1.0_wp, state)
        call check(suite, all(stress == 0.0_wp), label//"stress free after an extension")
        call check_close(suite, state(3), 3.0_wp*e0, tol*e0, label//"opening = volume change")
        ! sheared while open: still stress free, the shear is plastic
        de = 0.0_wp
        de(4) = 0.5_wp*e0
        call mat%update_stress(stress, de, zero3, 1.0_wp, state)
        call check(suite, all(stress == 0.0_wp), label//"stress free under shear while open")
        call check_close(suite, state(1), e0/sqrt(3.0_wp), tol*e0, &
            label//"shear while open is plastic (eps_q = 2 e_xy / sqrt(3))")
        call check_close(suite, state(3), 3.0_wp*e0, tol*e0, label//"shear keeps the opening")
        ! compressed by part of the opening: closes partly, no stress
        call mat%update_stress(stress, isotropic(-0.5_wp*e0, n), zero3, 1.0_wp, state)
        call check(suite, all(stress == 0.0_wp), label//"no stress while closing")
        call check_close(suite, state(3), 1.5_wp*e0, tol*e0, label//"opening closes by the compression")
        ! compressed past closure: the rest loads with the bulk modulus
        call mat%update_stress(stress, isotropic(-e0, n), zero3, 1.0_wp, state)
        call check(suite, state(3) == 0.0_wp, label//"closed")
        call check_close(suite, stress(1), -bulk*1.5_wp*e0, tol*bulk*e0, &
            label//"compression beyond closure: sigma = K (dV/V - opening)")
        call check_close(suite, stress(3), stress(1), tol*bulk*e0, label//"isotropic stress")
        call check(suite, all(abs(stress(4:)) <= tol*bulk*e0), label//"no shear stress")
        ! unloading from compression into tension opens again only beyond zero stress
        call mat%update_stress(stress, isotropic(2.0_wp*e0, n), zero3, 1.0_wp, state)
        call check(suite, all(stress == 0.0_wp), label//"stress free after the extension")
        call check_close(suite, state(3), 4.5_wp*e0, tol*e0, &
            label//"opening = extension beyond the elastic recovery (6 e0 - 1.5 e0)")
    end subroutine check_cycle

    subroutine check_without(mat, name, n)
        class(material_type), intent(in) :: mat
        character(len=*), intent(in) :: name
        integer, intent(in) :: n
        real(wp) :: stress(n), state(2), tol
        character(len=:), allocatable :: label

        label = name//merge(" 2D", " 3D", n == 4)//" without separation: "
        tol = 10.0_wp*epsilon(1.0_wp)
        stress = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(stress, isotropic(e0, n), zero3, 1.0_wp, state)
        call check(suite, all(abs(stress) <= tol*bulk*e0), label//"stress free after an extension")
        call mat%update_stress(stress, isotropic(-0.5_wp*e0, n), zero3, 1.0_wp, state)
        call check_close(suite, stress(1), -bulk*1.5_wp*e0, tol*bulk*e0, &
            label//"compression loads at once (the dilation stays)")
    end subroutine check_without

end program test_mpm_separation
