!> mu(I) material: at zero rate the Drucker-Prager plane-strain cone and Mohr-Coulomb of
!> sin(phi) = mu_s, the steady shear stress mu(I) p at a given shear rate (closed form, 2D and
!> 3D), the limit mu_2 as I grows without bound, no stress without pressure (separation), and
!> the reading of its keys (each bad value an input error, exit code 2).
program test_mpm_material_mu_i
    use, intrinsic :: ieee_arithmetic, only: ieee_is_finite
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, exit_input
    use mpm_json, only: json_document_type, json_parse_string, json_root, json_free
    use mpm_case_cursor, only: cursor_type, new_cursor
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, check_contains, finish
    use mpm_strength, only: strength_type
    use mpm_material_drucker_prager, only: drucker_prager_material_type, &
        new_drucker_prager_material, cone_plane_strain
    use mpm_material_mohr_coulomb, only: mohr_coulomb_material_type, new_mohr_coulomb_material
    use mpm_material_mu_i, only: mu_i_material_type, new_mu_i_material, mu_i_friction, &
        mu_i_inertial_number
    implicit none

    type(test_suite_type) :: suite
    real(wp), parameter :: young = 1.0e7_wp, poisson = 0.3_wp
    real(wp), parameter :: bulk = young/(3*(1 - 2*poisson)), shear = young/(2*(1 + poisson))
    ! glass beads of REFERENCES.md section 11 (Jop et al. 2006)
    real(wp), parameter :: deg = acos(-1.0_wp)/180.0_wp
    real(wp), parameter :: mu_s = tan(20.9_wp*deg), mu_2 = tan(32.76_wp*deg), i_0 = 0.279_wp
    real(wp), parameter :: diameter = 0.5e-3_wp, solid = 2450.0_wp
    real(wp), parameter :: p0 = 1.0e3_wp     ! confining pressure [Pa]
    real(wp), parameter :: eps = epsilon(1.0_wp)
    real(wp), parameter :: zero3(3) = 0.0_wp

    call new_suite(suite, "mpm_material_mu_i")
    call check_zero_rate_drucker_prager()
    call check_zero_rate_mohr_coulomb()
    call check_steady_shear(2, 1.0_wp)
    call check_steady_shear(2, 30.0_wp)
    call check_steady_shear(3, 300.0_wp)
    call check_rate_limit()
    call check_no_pressure()
    call check_reading()
    call finish(suite)

contains

    !> The test material (separation as given).
    subroutine new_material(mat, separation)
        type(mu_i_material_type), intent(out) :: mat
            !! the material
        logical, intent(in) :: separation
            !! keep the opening

        call new_mu_i_material(mat, bulk, shear, 2000.0_wp, mu_s, mu_2, i_0, diameter, solid, &
            separation)
    end subroutine new_material

    !> Zero rate (dt = 1e12 s for strain increments of 1e-4: I ~ 1e-20) and the Drucker-Prager
    !> plane-strain cone of phi = asin(mu_s), psi = 0, c = 0 (alpha = sin(phi) = mu_s, k = 0)
    !> return to the same stress at every step of a 2D path that loads, flows, unloads, turns and
    !> passes through tension (the apex), and accumulate the same eps_q. Both are radial returns
    !> at constant mean stress; they differ by mu(I) - mu_s <= dmu I / I_0 ~ 1e-20 and by the
    !> round-off of their different operations, a few eps of the stress per step, which the
    !> returns do not let grow (40 eps of the largest stress seen): tol 100 eps of it.
    subroutine check_zero_rate_drucker_prager()
        type(mu_i_material_type) :: mat
        type(drucker_prager_material_type) :: dp
        type(strength_type) :: strength
        real(wp) :: s(4), sd(4), st(1), std(2), de(4), worst, worst_q, biggest
        integer :: i

        call new_material(mat, .false.)
        strength%friction = asin(mu_s)
        call new_drucker_prager_material(dp, young, poisson, 2000.0_wp, strength, &
            cone_plane_strain)
        s = [-p0, -0.8_wp*p0, -p0, 0.0_wp]
        sd = s
        st = 0.0_wp
        std = 0.0_wp
        worst = 0.0_wp
        worst_q = 0.0_wp
        biggest = 0.0_wp
        do i = 1, 400
            de = path_increment(i)
            call mat%update_stress(s, de, [0.01_wp*de(4), 0.0_wp, 0.0_wp], 1.0e12_wp, st)
            call dp%update_stress(sd, de, [0.01_wp*de(4), 0.0_wp, 0.0_wp], 1.0e12_wp, std)
            worst = max(worst, maxval(abs(s - sd)))
            biggest = max(biggest, maxval(abs(sd)))
            worst_q = max(worst_q, abs(st(1) - std(1)))
        end do
        call check(suite, st(1) > 1.0e-3_wp, "zero rate: the path flows (eps_q > 1e-3)")
        call check_close(suite, worst, 0.0_wp, 100*eps*biggest, &
            "zero rate: stress of the Drucker-Prager plane-strain cone, alpha = mu_s")
        call check_close(suite, worst_q, 0.0_wp, 1.0e3_wp*eps, "zero rate: the same eps_q")
    end subroutine check_zero_rate_drucker_prager

    !> Strain increment i of the path of check_zero_rate_drucker_prager: shear with some
    !> compression, reversed shear, then extension into tension and back.
    pure function path_increment(i) result(de)
        integer, intent(in) :: i
            !! step
        real(wp) :: de(4)
            !! strain increment [-]

        if (i <= 150) then
            de = [-2.0e-6_wp, 1.0e-6_wp, 0.0_wp, 1.0e-4_wp]
        else if (i <= 300) then
            de = [1.0e-6_wp, -3.0e-6_wp, 0.0_wp, -1.0e-4_wp]
        else if (i <= 350) then
            de = [4.0e-5_wp, 2.0e-5_wp, 0.0_wp, 1.0e-5_wp]
        else
            de = [-4.0e-5_wp, -3.0e-5_wp, 0.0_wp, 0.0_wp]
        end if
    end function path_increment

    !> Plane-strain simple shear at zero rate from an isotropic p0: Mohr-Coulomb with psi = 0
    !> yields when the in-plane Mohr circle (centre -p0, radius tau) touches its line,
    !> tau = p0 sin(phi), and flows there at constant volume; mu(I) with mu_s = sin(phi)
    !> holds tau = mu_s p0. Round-off: tol 100 eps p0.
    subroutine check_zero_rate_mohr_coulomb()
        type(mu_i_material_type) :: mat
        type(mohr_coulomb_material_type) :: mc
        type(strength_type) :: strength
        real(wp) :: s(4), sm(4), st(1), stm(2)
        integer :: i

        call new_material(mat, .false.)
        strength%friction = asin(mu_s)
        call new_mohr_coulomb_material(mc, young, poisson, 2000.0_wp, strength)
        s = [-p0, -p0, -p0, 0.0_wp]
        sm = s
        st = 0.0_wp
        stm = 0.0_wp
        do i = 1, 100
            call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 1.0e-5_wp], zero3, 1.0e6_wp, st)
            call mc%update_stress(sm, [0.0_wp, 0.0_wp, 0.0_wp, 1.0e-5_wp], zero3, 1.0e6_wp, stm)
        end do
        call check_close(suite, sm(4), sin(asin(mu_s))*p0, 100*eps*p0, &
            "zero rate: Mohr-Coulomb simple shear gives tau = p0 sin(phi)")
        call check_close(suite, s(4), sm(4), 100*eps*p0, &
            "zero rate: mu(I) shear stress = Mohr-Coulomb's, sin(phi) = mu_s")
        call check(suite, maxval(abs(s(1:3) + p0)) <= 100*eps*p0 .and. &
            maxval(abs(sm(1:3) + p0)) <= 100*eps*p0, "zero rate: pressure kept by both")
    end subroutine check_zero_rate_mohr_coulomb

    !> Steady simple shear at rate gamma_dot under p0 (strain increment gamma_dot dt / 2 on a
    !> shear component, no spin): once the stress no longer changes the whole rate is plastic,
    !> so tau = mu(I) p0 with I = gamma_dot d / sqrt(p0 / rho_s), the closed form of Jop et al.
    !> (2006), and p stays p0 (no dilatancy). The returns converge geometrically to it, by a
    !> factor p mu'(gamma_dot) / (p mu' + G dt) < 0.04 per step here, so 400 steps leave
    !> nothing of the start; round-off: tol 100 eps p0.
    subroutine check_steady_shear(dim, rate)
        integer, intent(in) :: dim
            !! 2 (shear xy) or 3 (shear yz)
        real(wp), intent(in) :: rate
            !! shear rate gamma_dot [1/s]

        type(mu_i_material_type) :: mat
        real(wp), parameter :: dt = 1.0e-5_wp
        real(wp), allocatable :: s(:), de(:)
        real(wp) :: st(2), tau, expected
        integer :: i, k
        character(len=48) :: tag

        write (tag, "(i0,a,es8.1,a)") dim, "D simple shear at ", rate, " 1/s:"
        call new_material(mat, .true.)
        allocate (s(2*dim), de(2*dim))
        s = 0.0_wp
        s(1:3) = -p0
        de = 0.0_wp
        k = merge(4, 5, dim == 2)
        de(k) = 0.5_wp*rate*dt
        st = 0.0_wp
        do i = 1, 400
            call mat%update_stress(s, de, zero3, dt, st)
        end do
        tau = s(k)
        expected = mu_i_friction(mat, mu_i_inertial_number(mat, rate, p0))*p0
        call check_close(suite, tau, expected, 100*eps*p0, trim(tag)//" tau = mu(I) p")
        call check(suite, expected > mu_s*p0*(1 + 1.0e-3_wp), trim(tag)//" above mu_s p")
        call check(suite, maxval(abs(s(1:3) + p0)) <= 100*eps*p0, trim(tag)//" p kept")
        call check(suite, all(abs(s(4:)) <= 100*eps*p0 .or. [(i == k, i = 4, 2*dim)]), &
            trim(tag)//" other shear stresses 0")
        call check_close(suite, st(1), 400*rate*dt/sqrt(3.0_wp), 0.02_wp*400*rate*dt, &
            trim(tag)//" eps_q ~ gamma / sqrt(3) (all but the elastic strain)")
    end subroutine check_steady_shear

    !> I without bound: grains of 1 m sheared at 1e4 1/s under p0 (I ~ 6e3), and a pressure of
    !> 1e-200 Pa (the edge of a thin front) at 10 1/s: tau / p -> mu_2, short of it by
    !> (mu_2 - mu_s) I_0 / (I_0 + I) (the closed form), never above; no overflow at p -> 0.
    subroutine check_rate_limit()
        type(mu_i_material_type) :: mat
        real(wp), parameter :: dt = 1.0e-5_wp, rate = 1.0e4_wp, tiny_p = 1.0e-200_wp
        real(wp) :: s(4), st(1), inertial, ratio
        integer :: i

        call new_mu_i_material(mat, bulk, shear, 2000.0_wp, mu_s, mu_2, i_0, 1.0_wp, solid, &
            .false.)
        s = [-p0, -p0, -p0, 0.0_wp]
        st = 0.0_wp
        do i = 1, 400
            call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 0.5_wp*rate*dt], zero3, dt, st)
        end do
        inertial = mu_i_inertial_number(mat, rate, p0)
        call check(suite, inertial > 1.0e3_wp, "rate limit: I > 1e3")
        call check_close(suite, s(4)/p0, mu_2 - (mu_2 - mu_s)*i_0/(i_0 + inertial), 100*eps, &
            "rate limit: tau / p = mu_2 - dmu I_0 / (I_0 + I)")
        call check(suite, s(4)/p0 < mu_2 .and. mu_2 - s(4)/p0 < (mu_2 - mu_s)*i_0/inertial*1.01, &
            "rate limit: tau / p within dmu I_0 / I below mu_2")
        ! one step at a vanishing pressure: the trial shear stress is far above mu_2 p
        s = [-tiny_p, -tiny_p, -tiny_p, 0.0_wp]
        call new_material(mat, .false.)
        call mat%update_stress(s, [0.0_wp, 0.0_wp, 0.0_wp, 5.0e-5_wp], zero3, dt, st)
        ratio = s(4)/tiny_p
        call check(suite, ieee_is_finite(ratio), "p = 1e-200 Pa: finite stress")
        call check_close(suite, ratio, mu_2, 1.0e-12_wp, "p = 1e-200 Pa: tau / p = mu_2")
    end subroutine check_rate_limit

    !> Without pressure the grains carry nothing: a trial stress in tension returns to zero;
    !> with separation the volume taken beyond zero pressure is the opening (state(2) = the
    !> trial mean stress / K), and compression first closes it, stress free, before the
    !> elastic response starts again.
    subroutine check_no_pressure()
        type(mu_i_material_type) :: mat
        real(wp) :: s(4), st(2)

        call new_material(mat, .true.)
        call check(suite, mat%nstate() == 2, "separation: two state values")
        s = [-10.0_wp, -10.0_wp, -10.0_wp, 0.0_wp]
        st = 0.0_wp
        call mat%update_stress(s, [1.0e-5_wp, 1.0e-5_wp, 0.0_wp, 0.0_wp], zero3, 1.0e-4_wp, st)
        call check(suite, all(s == 0.0_wp), "tension: stress free")
        call check_close(suite, st(2), (bulk*2.0e-5_wp - 10.0_wp)/bulk, 100*eps, &
            "tension: opening = trial mean stress / K")
        call mat%update_stress(s, [-1.0e-6_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, 1.0e-4_wp, st)
        call check(suite, all(s == 0.0_wp) .and. st(2) > 0.0_wp, "compression: closes, stress free")
        call mat%update_stress(s, [-2.0e-5_wp, 0.0_wp, 0.0_wp, 0.0_wp], zero3, 1.0e-4_wp, st)
        call check(suite, st(2) == 0.0_wp .and. sum(s(1:3)) < 0.0_wp, &
            "compression beyond closure: stress again")
        call new_material(mat, .false.)
        call check(suite, mat%nstate() == 1, "no separation: one state value")
    end subroutine check_no_pressure

    !> Keys read through the cursor: a valid object (E/nu and K/G give the same moduli), and
    !> each bad value an input error (exit code 2) whose message names the key.
    subroutine check_reading()
        type(mu_i_material_type) :: mat
        type(error_type), allocatable :: error
        character(len=*), parameter :: rheo = '"rho": 2000, "mu_s": 0.38, "mu_2": 0.64, ' &
            //'"I_0": 0.279, "grain_diameter": 5e-4, "grain_density": 2450'

        call read_object('{"E": 1e7, "nu": 0.3, '//rheo//'}', mat, error)
        call check(suite, .not. allocated(error), "reads E, nu and the rheology")
        call check_close(suite, mat%shear, shear, 10*eps*shear, "E, nu: G")
        call check(suite, mat%separation, "separation by default")
        call read_object('{"K": 5e6, "G": 3e6, "separation": false, '//rheo//'}', mat, error)
        call check(suite, .not. allocated(error), "reads K, G")
        call check_close(suite, mat%bulk, 5.0e6_wp, 10*eps*5.0e6_wp, "K, G: K")
        call check_close(suite, mat%shear, 3.0e6_wp, 10*eps*3.0e6_wp, "K, G: G")
        call check_close(suite, mat%wave_speed(), sqrt((5.0e6_wp + 4*3.0e6_wp/3)/2000), &
            1.0e-12_wp, "K, G: wave speed")
        call check(suite, .not. mat%separation, "separation false")
        call bad('{"E": 1e7, "nu": 0.3, "K": 5e6, '//rheo//'}', "both E/nu and K/G")
        call bad('{"K": 5e6, '//rheo//'}', "materials[1].G")
        call bad('{"K": 1e6, "G": 3e6, '//rheo//'}', "nu")
        call bad('{"E": 1e7, "nu": 0.5, '//rheo//'}', "materials[1].nu")
        call bad('{"E": 1e7, "nu": 0.3, "rho": 2000, "mu_s": 0.38, "mu_2": 0.3, "I_0": 0.279, ' &
            //'"grain_diameter": 5e-4, "grain_density": 2450}', "materials[1].mu_2")
        call bad('{"E": 1e7, "nu": 0.3, "rho": 2000, "mu_s": 0, "mu_2": 0.3, "I_0": 0.279, ' &
            //'"grain_diameter": 5e-4, "grain_density": 2450}', "materials[1].mu_s")
        call bad('{"E": 1e7, "nu": 0.3, "rho": 2000, "mu_s": 0.38, "mu_2": 0.64, "I_0": -1, ' &
            //'"grain_diameter": 5e-4, "grain_density": 2450}', "materials[1].I_0")
        call bad('{"E": 1e7, "nu": 0.3, "rho": 2000, "mu_s": 0.38, "mu_2": 0.64, "I_0": 0.279, ' &
            //'"grain_density": 2450}', "materials[1].grain_diameter")
        call bad('{"E": 1e7, "nu": 0.3, "rho": 2000, "mu_s": 0.38, "mu_2": 0.64, "I_0": 0.279, ' &
            //'"grain_diameter": 5e-4, "grain_density": 0}', "materials[1].grain_density")
        call bad('{"E": 1e7, "nu": 0.3, '//rheo//', "separation": 1}', "materials[1].separation")
    end subroutine check_reading

    !> A bad object: an input error whose message holds `part`.
    subroutine bad(text, part)
        character(len=*), intent(in) :: text
            !! the material object
        character(len=*), intent(in) :: part
            !! what the message must name

        type(mu_i_material_type) :: mat
        type(error_type), allocatable :: error

        call read_object(text, mat, error)
        call check(suite, allocated(error), "refused: "//part)
        if (.not. allocated(error)) return
        call check(suite, error%code == exit_input, "exit code 2: "//part)
        call check_contains(suite, error%message, part, "message names "//part)
        call check_contains(suite, error%message, "example: ", "message names the file")
    end subroutine bad

    !> Read a material object given as text.
    subroutine read_object(text, mat, error)
        character(len=*), intent(in) :: text
            !! the material object
        type(mu_i_material_type), intent(inout) :: mat
            !! the material
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(json_document_type) :: doc
        type(cursor_type) :: item

        call json_parse_string(text, doc, error, "example")
        if (allocated(error)) return
        item = new_cursor(json_root(doc), "materials[1]", "example")
        call mat%read(item, error)
        call json_free(doc)
    end subroutine read_object

end program test_mpm_material_mu_i
