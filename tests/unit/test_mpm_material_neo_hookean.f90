!> Neo-Hookean material: uniaxial stretch against the closed form (including the 1D law
!> sigma = E/2 (F - 1/F) of the manufactured solution at nu = 0), 2D plane strain against 3D,
!> and objectivity under a rigid rotation.
program test_mpm_material_neo_hookean
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_material_neo_hookean, only: neo_hookean_material_type, new_neo_hookean_material
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_material_neo_hookean")
    call check_uniaxial(0.0_wp)
    call check_uniaxial(0.3_wp)
    call check_rotation()
    call finish(suite)

contains

    function material(poisson) result(mat)
        real(wp), intent(in) :: poisson
        type(neo_hookean_material_type) :: mat
        call new_neo_hookean_material(mat, "rubber", 1.0e6_wp, poisson, 1000.0_wp)
    end function material

    !> Stretch F = diag(s, 1, 1) to s = 1.5 and compress to 0.6 in increments chosen so the
    !> integrated F is exactly s at every step: sigma_xx = mu/J (s^2 - 1) + lambda ln(J)/J,
    !> sigma_yy = sigma_zz = lambda ln(J)/J, J = s; round-off tolerance.
    subroutine check_uniaxial(poisson)
        real(wp), intent(in) :: poisson

        type(neo_hookean_material_type) :: mat
        real(wp) :: s6(6), s4(4), state6(9), state4(9), stretch, next, mu, lam, tol
        integer :: k
        character(len=16) :: label

        write (label, "(a,f3.1)") "nu = ", poisson
        mat = material(poisson)
        mu = mat%shear
        lam = mat%lame
        s6 = 0.0_wp
        s4 = 0.0_wp
        state6 = 0.0_wp
        state4 = 0.0_wp
        stretch = 1.0_wp
        tol = 1.0e3_wp*epsilon(1.0_wp)*1.0e6_wp
        do k = 1, 200
            if (k <= 100) then
                next = 1.0_wp + 0.5_wp*k/100.0_wp
            else
                next = 1.5_wp - 0.9_wp*(k - 100)/100.0_wp
            end if
            call mat%update_stress(s6, [(next - stretch)/stretch, 0.0_wp, 0.0_wp, 0.0_wp, &
                0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp, state6)
            call mat%update_stress(s4, [(next - stretch)/stretch, 0.0_wp, 0.0_wp, 0.0_wp], &
                [0.0_wp, 0.0_wp, 0.0_wp], 1.0_wp, state4)
            stretch = next
            if (k == 100 .or. k == 200) then
                call check_close(suite, s6(1), mu/stretch*(stretch**2 - 1) &
                    + lam*log(stretch)/stretch, tol, trim(label)//": sigma_xx")
                call check_close(suite, s6(2), lam*log(stretch)/stretch, tol, &
                    trim(label)//": sigma_yy")
                call check(suite, all(abs(s4 - s6(1:4)) <= tol), &
                    trim(label)//": plane strain equals 3D under uniaxial strain")
                if (poisson == 0.0_wp) call check_close(suite, s6(1), &
                    0.5_wp*1.0e6_wp*(stretch - 1/stretch), tol, &
                    "nu = 0: sigma = E/2 (F - 1/F)")
            end if
        end do
    end subroutine check_uniaxial

    !> Stretch, then turn rigidly by 90 degrees in N steps: the stress turns with the body
    !> (sigma_xx <-> sigma_yy). Each first-order increment I + Omega has det 1 + w^2, so F
    !> grows by about theta^2 / (2N) over the turn; the stress error is at most the P-wave
    !> modulus times twice that (B = F F^T doubles it).
    subroutine check_rotation()
        type(neo_hookean_material_type) :: mat
        real(wp) :: s(4), state(9), before(4), theta, tol
        integer :: k
        integer, parameter :: nstep = 20000

        mat = material(0.3_wp)
        s = 0.0_wp
        state = 0.0_wp
        call mat%update_stress(s, [0.2_wp, 0.0_wp, 0.0_wp, 0.0_wp], [0.0_wp, 0.0_wp, 0.0_wp], &
            1.0_wp, state)
        before = s
        theta = acos(-1.0_wp)/2
        do k = 1, nstep
            call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.0_wp], &
                [-theta/nstep, 0.0_wp, 0.0_wp], 1.0_wp, state)
        end do
        tol = 2.0_wp*(mat%lame + 2.0_wp*mat%shear)*theta**2/(2.0_wp*nstep)*2.0_wp
        call check_close(suite, s(2), before(1), tol, "rotation: sigma_yy takes sigma_xx")
        call check_close(suite, s(1), before(2), tol, "rotation: sigma_xx takes sigma_yy")
        call check_close(suite, s(3), before(3), tol, "rotation: sigma_zz unchanged")
        call check_close(suite, s(4), 0.0_wp, tol, "rotation: no shear")
    end subroutine check_rotation

end program test_mpm_material_neo_hookean
