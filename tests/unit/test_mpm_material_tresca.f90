!> Tresca / von Mises undrained clay (`materials[i].type = "tresca"`).
!>
!> Closed forms: in plane strain simple shear the stress reaches (sigma_1 - sigma_3) / 2 = Su
!> and stays there, the mean stress unchanged (isochoric plastic flow), as Mohr-Coulomb with
!> phi = 0 and c = Su; with match = "compression", an isochoric triaxial compression reaches
!> q = 2 Su; the plastic shear strain grows by the plastic part of the shear; Su(z) = Su +
!> gradient (elevation - z) below the elevation, Su above it; linear softening halves the
!> strength (sensitivity 2) at the softening strain and at 3/4 at half of it; the strength
!> reduction divides Su and its gradient by F; the case reader refuses Su < 0, Su = 0 without
!> a gradient, Su_elevation without a gradient and a sensitivity below 1.
program test_mpm_material_tresca
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_testing_case, only: soil_case, expect_error
    use mpm_softening, only: softening_none, softening_linear
    use mpm_strength, only: strength_type
    use mpm_material_tresca, only: tresca_material_type, new_tresca_material, &
        match_plane_strain, match_compression
    use mpm_material_mohr_coulomb, only: mohr_coulomb_material_type, new_mohr_coulomb_material
    use mpm_stress, only: mean_and_deviator
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: young = 3.0e6_wp, poisson = 0.49_wp, su = 2.0e4_wp

    call new_suite(suite, "mpm_material_tresca")
    call plane_strain_shear()
    call triaxial_compression()
    call profile_and_softening()
    call refused()
    call finish(suite)

contains

    subroutine plane_strain_shear()
        type(tresca_material_type) :: mat
        type(mohr_coulomb_material_type) :: mc
        type(strength_type) :: strength
        real(wp) :: stress(4), mc_stress(4), state(2), mc_state(2), de(4), t, m, dev(4), rho
        real(wp) :: m0, elastic_limit
        integer :: i
        integer, parameter :: nsteps = 1000

        call new_tresca_material(mat, young, poisson, 2000.0_wp, su, 0.0_wp, 0.0_wp, &
            match_plane_strain, softening_none, 1.0_wp, 0.0_wp)
        strength%cohesion = su
        strength%cohesion_residual = su
        call new_mohr_coulomb_material(mc, young, poisson, 2000.0_wp, strength)
        ! a K0 start inside the surface (sqrt(J2) = 1.15e4 Pa)
        stress = [-8.0e4_wp, -1.0e5_wp, -8.0e4_wp, 0.0_wp]
        mc_stress = stress
        m0 = sum(stress(1:3))/3.0_wp
        state = [0.0_wp, su]
        mc_state = 0.0_wp
        de = [0.0_wp, 0.0_wp, 0.0_wp, 2.0e-4_wp]   ! tensor shear strain increment
        do i = 1, nsteps
            call mat%update_stress(stress, de, [0.0_wp, 0.0_wp, 0.0_wp], 1.0e-3_wp, state)
            call mc%update_stress(mc_stress, de, [0.0_wp, 0.0_wp, 0.0_wp], 1.0e-3_wp, mc_state)
        end do
        t = sqrt(0.25_wp*(stress(1) - stress(2))**2 + stress(4)**2)
        ! (von Mises in plane strain reaches Tresca's Su as the out-of-plane deviator decays)
        call check_close(suite, t, su, 1.0e-6_wp*su, "plane strain: (sigma_1 - sigma_3)/2 = Su")
        call mean_and_deviator(stress, m, dev, rho)
        call check_close(suite, rho, su, 1.0e-11_wp*su, "sqrt(J2) = Su (k of plane_strain)")
        call check_close(suite, m, m0, 1.0e-11_wp*abs(m0), "mean stress unchanged (undrained)")
        t = sqrt(0.25_wp*(mc_stress(1) - mc_stress(2))**2 + mc_stress(4)**2)
        call check_close(suite, t, su, 1.0e-11_wp*su, "Mohr-Coulomb phi = 0 reaches the same Su")
        ! from an isotropic start the flow is pure shear: the plastic shear strain is the total
        ! engineering shear nsteps * 4e-4 minus the elastic Su / G, over sqrt(3)
        stress = [-8.0e4_wp, -8.0e4_wp, -8.0e4_wp, 0.0_wp]
        state = [0.0_wp, su]
        do i = 1, nsteps
            call mat%update_stress(stress, de, [0.0_wp, 0.0_wp, 0.0_wp], 1.0e-3_wp, state)
        end do
        elastic_limit = su/mat%shear
        call check_close(suite, state(1), (nsteps*4.0e-4_wp - elastic_limit)/sqrt(3.0_wp), &
            1.0e-12_wp, "plastic shear strain = plastic engineering shear / sqrt(3)")
        call check_close(suite, stress(4), su, 1.0e-11_wp*su, "pure shear: tau_xy = Su")
    end subroutine plane_strain_shear

    subroutine triaxial_compression()
        type(tresca_material_type) :: mat
        real(wp) :: stress(6), state(2), de(6), q
        integer :: i

        call new_tresca_material(mat, young, poisson, 2000.0_wp, su, 0.0_wp, 0.0_wp, &
            match_compression, softening_none, 1.0_wp, 0.0_wp)
        stress = [-1.0e5_wp, -1.0e5_wp, -1.0e5_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        state = [0.0_wp, su]
        ! isochoric: axial -2e, lateral +e, along z
        de = [1.0e-4_wp, 1.0e-4_wp, -2.0e-4_wp, 0.0_wp, 0.0_wp, 0.0_wp]
        do i = 1, 100
            call mat%update_stress(stress, de, [0.0_wp, 0.0_wp, 0.0_wp], 1.0e-3_wp, state)
        end do
        q = stress(1) - stress(3)
        call check_close(suite, q, 2.0_wp*su, 1.0e-11_wp*su, "compression match: q = 2 Su")
    end subroutine triaxial_compression

    subroutine profile_and_softening()
        type(tresca_material_type) :: mat, soft
        real(wp) :: state(2)
        logical :: reduced

        call new_tresca_material(mat, young, poisson, 2000.0_wp, 1.0e4_wp, 2.0e3_wp, 5.0_wp, &
            match_plane_strain, softening_none, 1.0_wp, 0.0_wp)
        state = 0.0_wp
        call mat%initial_state([1.0_wp, 2.0_wp], state)
        call check(suite, state(2) == 2.0_wp, "the initial elevation is the state")
        call check(suite, mat%needs_initial_state(), "a gradient needs the initial elevation")
        ! Su 3 m below the elevation: the first plastic step of pure shear returns to k = Su(z)
        call check_close(suite, yield_radius(mat, 2.0_wp), 1.6e4_wp, 1.0e-10_wp, &
            "Su 3 m below: Su + 3 gradient")
        call check_close(suite, yield_radius(mat, 7.0_wp), 1.0e4_wp, 1.0e-10_wp, &
            "Su above its elevation: Su")
        call new_tresca_material(soft, young, poisson, 2000.0_wp, 1.0e4_wp, 2.0e3_wp, 5.0_wp, &
            match_plane_strain, softening_linear, 2.0_wp, 0.1_wp)
        call check_close(suite, soft%strength_at(1.6e4_wp, 0.0_wp), 1.6e4_wp, 1.0e-10_wp, &
            "peak strength")
        call check_close(suite, soft%strength_at(1.6e4_wp, 0.05_wp), 1.2e4_wp, 1.0e-10_wp, &
            "linear softening halfway: 3/4 of the peak (St = 2)")
        call check_close(suite, soft%strength_at(1.6e4_wp, 0.5_wp), 0.8e4_wp, 1.0e-10_wp, &
            "residual: peak / St")
        call mat%reduce_strength(2.0_wp, reduced)
        call check(suite, reduced .and. mat%su == 5.0e3_wp .and. mat%su_gradient == 1.0e3_wp, &
            "strength reduction divides Su and its gradient")
        call check_close(suite, yield_radius(mat, 2.0_wp), 0.8e4_wp, 1.0e-10_wp, &
            "a reduced particle's Su: (Su + 3 gradient) / F")
        call new_tresca_material(mat, young, poisson, 2000.0_wp, 1.0e4_wp, 0.0_wp, 0.0_wp, &
            match_plane_strain, softening_none, 1.0_wp, 0.0_wp)
        call check(suite, .not. mat%needs_initial_state(), "a constant Su needs no state")
        call check_close(suite, yield_radius(mat, 0.0_wp), 1.0e4_wp, 1.0e-10_wp, &
            "constant Su whatever the state (a particle from load_state)")
    end subroutine profile_and_softening

    !> sqrt(J2) after a large shear step from rest, for a particle of initial elevation z0:
    !> the radius of the yield cylinder (no softening).
    real(wp) function yield_radius(mat, z0)
        type(tresca_material_type), intent(in) :: mat
        real(wp), intent(in) :: z0

        real(wp) :: stress(4), state(2), m, dev(4)

        stress = -1.0e5_wp
        stress(4) = 0.0_wp
        state = [0.0_wp, z0]
        call mat%update_stress(stress, [0.0_wp, 0.0_wp, 0.0_wp, 0.1_wp], [0.0_wp, 0.0_wp, &
            0.0_wp], 1.0e-3_wp, state)
        call mean_and_deviator(stress, m, dev, yield_radius)
    end function yield_radius

    subroutine refused()
        character(len=*), parameter :: base = '"type": "tresca", "E": 1e6, "nu": 0.49, "rho": 1800'

        call expect_error(suite, soil_case(base//', "Su": -1'), [character(len=200) :: &
            "materials[1].Su = -1 is out of range: must be >= 0 [Pa]"], "Su below zero")
        call expect_error(suite, soil_case(base//', "Su": 0'), [character(len=200) :: &
            "materials[1].Su = 0 with no Su_gradient leaves no strength"], "Su zero")
        call expect_error(suite, soil_case(base//', "Su": 1e4, "Su_elevation": 3'), &
            [character(len=200) :: "materials[1].Su_elevation only applies with " &
            //"materials[1].Su_gradient"], "elevation without gradient")
        call expect_error(suite, soil_case(base//', "Su": 1e4, "Su_gradient": 1e3'), &
            [character(len=200) :: "missing required key 'materials[1].Su_elevation'"], &
            "gradient without elevation")
        call expect_error(suite, soil_case(base//', "Su": 1e4, "softening": {"type": ' &
            //'"linear", "sensitivity": 0.5, "strain": 0.1}'), [character(len=200) :: &
            "materials[1].softening.sensitivity = 0.5 is out of range: must be >= 1"], &
            "sensitivity below 1")
        call expect_error(suite, soil_case(base//', "Su": 1e4, "match": "triaxial"'), &
            [character(len=200) :: "materials[1].match", '"plane_strain", "compression"'], &
            "unknown match")
    end subroutine refused

end program test_mpm_material_tresca
