!> Mohr-Coulomb elasto-plasticity with non-associated flow, a tension cut-off and softening
!> of the strength with the plastic shear strain.
!>
!> Stress is tension positive (`mpm_stress`). With the principal stresses ordered
!> s1 >= s2 >= s3, the elastic domain is
!>
!> - Mohr-Coulomb: f = (s1 - s3) + (s1 + s3) sin(phi) - 2 c cos(phi) <= 0,
!> - tension cut-off: s1 <= sigma_t,
!>
!> with the plastic potential g = (s1 - s3) + (s1 + s3) sin(psi) (dilatancy angle psi) on the
!> Mohr-Coulomb planes and an associated (Rankine) flow g = s1 on the cut-off.
!> sigma_t = min(tension_cutoff, c cot(phi)) when a cut-off is given; without one the apex
!> c cot(phi) of the pyramid limits the tension (phi = 0, Tresca, has no apex and then no
!> tensile limit).
!>
!> Return mapping (exact for the strength of the start of the step, since every surface is a
!> plane in principal stress space and linear elasticity is isotropic): the trial stress is
!> decomposed into principal values and directions (2D plane strain: the in-plane 2x2 in
!> closed form plus s_zz; 3D: cyclic Jacobi rotations to round-off, robust for repeated
!> eigenvalues), ordered, and returned in principal space as a multi-surface problem,
!> sigma = sigma_trial - sum_i dlambda_i D b_i with dlambda_i >= 0 (D the elastic stiffness,
!> b_i the flow direction of plane i). The planes of the ordered sextant and of its mirror
!> images that can become active are
!>
!> - A: (s1 - s3) + (s1 + s3) sin(phi) = 2 c cos(phi)  (the main plane),
!> - B: (s1 - s2) + (s1 + s2) sin(phi) = 2 c cos(phi)  (meets A on the extension edge s2 = s3),
!> - C: (s2 - s3) + (s2 + s3) sin(phi) = 2 c cos(phi)  (meets A on the compression edge s1 = s2),
!> - T1, T2, T3: s1 = sigma_t, s2 = sigma_t, s3 = sigma_t (the cut-off and its mirrors).
!>
!> The candidates are tried in order: the face A; the cut-off face T1; the extension edge A+B;
!> the compression edge A+C; the line A+T1 where the pyramid meets the cut-off; the line T1+T2
!> (s1 = s2 = sigma_t); the corner A+B+T1 (sigma_t, s, s); the corner (sigma_t, sigma_t, s)
!> where four planes A, C, T1, T2 meet (tested as its four sets of three planes); the corner
!> (sigma_t, sigma_t, sigma_t). A candidate is accepted when all its multipliers are
!> non-negative, its stress stays ordered and it violates no other plane (to round-off).
!> The matrices a_i . D b_j of the pairs have positive determinants, for example
!> 2 G (1 - sin(phi))(1 - sin(psi)) (a_A . D b_A + a_A . D b_B) for A+B and
!> 4 G (G + lambda)(1 - sin(phi))(1 - sin(psi)) for A+T1, so the edge returns are unique;
!> that at most one candidate is valid, and with a cut-off always one, was checked by
!> sampling trial stresses against an independent enumeration of all active sets (if round-off
!> at a region boundary rejects all, the least violating candidate is taken). Without a
!> cut-off, a trial stress that no face or edge accepts returns to the apex
!> c cot(phi) (1, 1, 1), as in de Souza Neto, Peric & Owen (Computational Methods for
!> Plasticity, 2008, ch. 8): with psi < phi the flow directions of the planes do not span the
!> apex region, so the apex is the return of what remains.
!> The returned principal values rebuild the stress with the principal directions of the
!> trial stress, as a correction sigma_trial - sum_k (s_k,trial - s_k) n_k n_k^T.
!>
!> Softening: phi, c and psi follow the accumulated plastic shear strain eps_q, taken at the
!> start of the step (explicit in the hardening variable, so each step is a return to fixed
!> planes: simple, exact for the step and stable for the small steps of explicit MPM).
!>
!> State of a particle: state(1) = accumulated equivalent plastic shear strain
!> eps_q = sum sqrt(2/3 de_p : de_p) (de_p the deviatoric plastic strain increment) [-],
!> state(2) = accumulated plastic volumetric strain, tension positive (dilation > 0) [-].
!>
!> With `separation` (see `mpm_separation`), state(3) = opening strain [-].
module mpm_material_mohr_coulomb
    use mpm_kinds, only: wp
    use mpm_softening, only: softening_weight
    use mpm_separation, only: close_opening
    use mpm_material, only: material_type
    use mpm_stress, only: add_jaumann_rotation, voigt_matrix
    use mpm_case, only: material_spec_type
    implicit none
    private
    public :: mohr_coulomb_material_type, new_mohr_coulomb_material

    !> Planes of the return: A, B, C (Mohr-Coulomb) and T1, T2, T3 (tension cut-off).
    integer, parameter :: plane_a = 1, plane_b = 2, plane_c = 3, plane_t1 = 4, plane_t2 = 5, &
        plane_t3 = 6
    !> Number of candidate sets of active planes (see the module documentation).
    integer, parameter :: ncandidates = 12
    !> Candidate sets of active planes, in the order they are tried (0: unused slot).
    integer, parameter :: candidates(3, ncandidates) = reshape([ &
        plane_a, 0, 0, &
        plane_t1, 0, 0, &
        plane_a, plane_b, 0, &
        plane_a, plane_c, 0, &
        plane_a, plane_t1, 0, &
        plane_t1, plane_t2, 0, &
        plane_a, plane_b, plane_t1, &
        plane_a, plane_c, plane_t1, &
        plane_a, plane_c, plane_t2, &
        plane_a, plane_t1, plane_t2, &
        plane_c, plane_t1, plane_t2, &
        plane_t1, plane_t2, plane_t3], [3, ncandidates])
    !> Relative round-off allowed in the yield check and in the tests of a candidate [-].
    real(wp), parameter :: tol_yield = 16.0_wp*epsilon(1.0_wp)
    real(wp), parameter :: tol_candidate = 64.0_wp*epsilon(1.0_wp)

    !> Mohr-Coulomb with tension cut-off, non-associated flow and softening.
    type, extends(material_type) :: mohr_coulomb_material_type
        real(wp) :: young = 0.0_wp
            !! Young's modulus E [Pa]
        real(wp) :: poisson = 0.0_wp
            !! Poisson's ratio nu [-]
        real(wp) :: shear = 0.0_wp
            !! shear modulus G [Pa]
        real(wp) :: lame = 0.0_wp
            !! first Lame parameter lambda [Pa]
        real(wp) :: friction = 0.0_wp
            !! peak friction angle phi [rad]
        real(wp) :: cohesion = 0.0_wp
            !! peak cohesion c [Pa]
        real(wp) :: dilatancy = 0.0_wp
            !! peak dilatancy angle psi [rad]
        real(wp) :: friction_residual = 0.0_wp
            !! residual friction angle [rad] (softening only)
        real(wp) :: cohesion_residual = 0.0_wp
            !! residual cohesion [Pa] (softening only)
        real(wp) :: dilatancy_residual = 0.0_wp
            !! residual dilatancy angle [rad] (softening only)
        integer :: softening = 0
            !! softening law (`softening_*` of `mpm_case`)
        real(wp) :: softening_strain = 0.0_wp
            !! linear: eps_q at which the residual values are reached; exponential: strain
            !! scale eta_0 [-]
        real(wp) :: tension_cutoff = -1.0_wp
            !! largest principal stress allowed [Pa]; negative: not given (the apex limits it)
        logical :: separation = .false.
            !! cohesionless separation (state(3) = opening strain)
    contains
        procedure :: update_stress => mohr_coulomb_update_stress
            !! exact return mapping of one particle over one step
        procedure :: nstate => mohr_coulomb_nstate
            !! two state values: eps_q and the plastic volumetric strain
        procedure :: strength => mohr_coulomb_strength
            !! phi, c, psi and the tensile strength after a given plastic shear strain
    end type mohr_coulomb_material_type

contains

    !> Construct a Mohr-Coulomb material from its case specification.
    pure subroutine new_mohr_coulomb_material(mat, spec)
        type(mohr_coulomb_material_type), intent(out) :: mat
            !! the material
        type(material_spec_type), intent(in) :: spec
            !! case specification (E, nu, rho, phi, c, psi, cut-off, softening)

        if (allocated(spec%name)) mat%name = spec%name
        mat%density = spec%density
        mat%young = spec%young
        mat%poisson = spec%poisson
        mat%shear = spec%young/(2.0_wp*(1.0_wp + spec%poisson))
        mat%lame = spec%young*spec%poisson/((1.0_wp + spec%poisson)*(1.0_wp - 2.0_wp*spec%poisson))
        mat%friction = spec%friction
        mat%cohesion = spec%cohesion
        mat%dilatancy = spec%dilatancy
        mat%friction_residual = spec%friction_residual
        mat%cohesion_residual = spec%cohesion_residual
        mat%dilatancy_residual = spec%dilatancy_residual
        mat%softening = spec%softening
        mat%softening_strain = spec%softening_strain
        mat%tension_cutoff = spec%tension_cutoff
        mat%separation = spec%separation
    end subroutine new_mohr_coulomb_material

    !> Two state values per particle, eps_q and the plastic volumetric strain, and with
    !> separation a third, the opening strain.
    pure integer function mohr_coulomb_nstate(self)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        mohr_coulomb_nstate = merge(3, 2, self%separation)
    end function mohr_coulomb_nstate

    !> Friction, cohesion, dilatancy and tensile strength after the plastic shear strain eps_q.
    !>
    !> Linear: x = x_p + (x_r - x_p) min(eps_q / eps_s, 1); exponential:
    !> x = x_r + (x_p - x_r) exp(-eps_q / eps_s); none: the peak values. The tensile strength is
    !> min(tension_cutoff, c cot(phi)) when a cut-off is given; `cutoff` is true only when it
    !> lies strictly below the apex c cot(phi) (or phi = 0), that is, when the cut-off planes
    !> are part of the surface.
    pure subroutine mohr_coulomb_strength(self, eps_q, friction, cohesion, dilatancy, tension, &
            cutoff)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: eps_q
            !! accumulated equivalent plastic shear strain [-]
        real(wp), intent(out) :: friction
            !! friction angle phi [rad]
        real(wp), intent(out) :: cohesion
            !! cohesion c [Pa]
        real(wp), intent(out) :: dilatancy
            !! dilatancy angle psi [rad]
        real(wp), intent(out) :: tension
            !! tensile strength sigma_t (when `cutoff`; else the apex, or huge for phi = 0) [Pa]
        logical, intent(out) :: cutoff
            !! whether the tension cut-off planes cut the pyramid below its apex

        real(wp) :: w, sphi, cphi

        w = softening_weight(self%softening, self%softening_strain, eps_q)
        friction = self%friction + w*(self%friction_residual - self%friction)
        cohesion = self%cohesion + w*(self%cohesion_residual - self%cohesion)
        dilatancy = self%dilatancy + w*(self%dilatancy_residual - self%dilatancy)

        sphi = sin(friction)
        cphi = cos(friction)
        ! sigma_t < c cot(phi) written without the division (phi may be 0)
        cutoff = self%tension_cutoff >= 0.0_wp .and. self%tension_cutoff*sphi < cohesion*cphi
        if (cutoff) then
            tension = self%tension_cutoff
        else if (has_apex(sphi, cohesion, cphi)) then
            tension = cohesion*cphi/sphi
        else
            tension = huge(1.0_wp)
        end if
    end subroutine mohr_coulomb_strength

    !> Whether the pyramid has an apex at a finite c cot(phi) worth computing: friction angles
    !> below machine epsilon are treated as Tresca (the apex would be beyond 1e15 c).
    pure logical function has_apex(sphi, cohesion, cphi)
        real(wp), intent(in) :: sphi
            !! sin(phi) [-]
        real(wp), intent(in) :: cohesion
            !! cohesion c [Pa]
        real(wp), intent(in) :: cphi
            !! cos(phi) [-]
        has_apex = sphi > epsilon(1.0_wp) .and. cohesion*cphi < sphi*huge(1.0_wp)
    end function has_apex

    !> Objective elastic predictor, then the return to the Mohr-Coulomb pyramid and cut-off.
    pure subroutine mohr_coulomb_update_stress(self, stress, dstrain, omega, dt, state)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        real(wp), intent(inout) :: stress(:)
            !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
        real(wp), intent(in) :: dstrain(:)
            !! strain increment D dt, tensor components [-]
        real(wp), intent(in) :: omega(3)
            !! spin increment W dt (xy, yz, zx) [-]
        real(wp), intent(in) :: dt
            !! time step [s] (unused: rate independent)
        real(wp), intent(inout) :: state(:)
            !! state(1) = eps_q [-], state(2) = plastic volumetric strain [-], with separation
            !! state(3) = opening strain [-]

        real(wp) :: friction, cohesion, dilatancy, tension, dvol, de(6), dplastic
        integer :: n
        real(wp) :: p(3), ps(3), dp(3), vec(3, 3), cos2, sin2, dev(3)
        integer :: order(3)
        logical :: cutoff, plastic, open

        call self%strength(state(1), friction, cohesion, dilatancy, tension, cutoff)

        n = size(dstrain)
        de(1:n) = dstrain
        if (self%separation) then
            call close_opening(de(1:n), state(3), state(1), open)
            if (open) then
                stress = 0.0_wp
                return
            end if
        end if
        dvol = de(1) + de(2) + de(3)
        call add_jaumann_rotation(stress, omega)
        stress = stress + 2.0_wp*self%shear*de(1:n)
        stress(1:3) = stress(1:3) + self%lame*dvol

        ! stresses clearly inside the surface (closed-form principal values) need no
        ! eigen-decomposition and no return
        if (clearly_elastic(stress, friction, cohesion, tension, cutoff)) return
        if (size(stress) == 4) then
            call principal_plane(stress, p, cos2, sin2)
        else
            call symmetric_eigen(stress(1:6), p, vec)
        end if
        order = descending_order(p)
        ps = p(order)
        call principal_return(ps, friction, cohesion, dilatancy, tension, cutoff, self%shear, &
            self%lame, plastic)
        if (.not. plastic) return

        ! correction of each principal value, in the order of the eigen-decomposition
        dp(order) = p(order) - ps
        if (size(stress) == 4) then
            stress(1) = stress(1) - 0.5_wp*(dp(1) + dp(2)) - 0.5_wp*(dp(1) - dp(2))*cos2
            stress(2) = stress(2) - 0.5_wp*(dp(1) + dp(2)) + 0.5_wp*(dp(1) - dp(2))*cos2
            stress(3) = stress(3) - dp(3)
            stress(4) = stress(4) - 0.5_wp*(dp(1) - dp(2))*sin2
        else
            stress(1) = stress(1) - sum(dp*vec(1, :)**2)
            stress(2) = stress(2) - sum(dp*vec(2, :)**2)
            stress(3) = stress(3) - sum(dp*vec(3, :)**2)
            stress(4) = stress(4) - sum(dp*vec(1, :)*vec(2, :))
            stress(5) = stress(5) - sum(dp*vec(2, :)*vec(3, :))
            stress(6) = stress(6) - sum(dp*vec(3, :)*vec(1, :))
        end if

        ! plastic strain D^-1 (sigma_trial - sigma), coaxial with the stress
        dev = (dp - sum(dp)/3.0_wp)/(2.0_wp*self%shear)
        state(1) = state(1) + sqrt(2.0_wp/3.0_wp*sum(dev**2))
        dplastic = sum(dp)/(3.0_wp*self%lame + 2.0_wp*self%shear)
        state(2) = state(2) + dplastic
        ! separation: a return to the stress-free apex opens the material by its dilation
        if (self%separation .and. dplastic > 0.0_wp .and. &
            all(abs(ps) <= tol_candidate*maxval(abs(p)))) then
            state(3) = state(3) + dplastic
            stress = 0.0_wp
        end if
    end subroutine mohr_coulomb_update_stress

    !> Whether a stress is inside the Mohr-Coulomb surface (and the cut-off) by a margin.
    !>
    !> The principal stresses come from the closed form of the eigenvalues of a symmetric 3x3
    !> matrix (trigonometric solution of the characteristic cubic), accurate to about
    !> sqrt(epsilon) of the deviatoric stress where two eigenvalues nearly coincide; the margin
    !> (1e-6 of the stress scale) is far above that, so a stress this test calls elastic is
    !> one the return leaves unchanged, and the eigen-decomposition is spared.
    pure logical function clearly_elastic(stress, friction, cohesion, tension, cutoff)
        real(wp), intent(in) :: stress(:)
            !! trial stress, 4 or 6 components, tension positive [Pa]
        real(wp), intent(in) :: friction, cohesion, tension
            !! phi [rad], c [Pa], sigma_t [Pa]
        logical, intent(in) :: cutoff
            !! whether the cut-off planes are part of the surface

        real(wp), parameter :: margin_factor = 1.0e-6_wp
        real(wp), parameter :: third_turn = 2.0_wp*acos(-1.0_wp)/3.0_wp
        real(wp) :: m, j2, sxy, syz, szx, b(3), r, scale, s1, s3, angle, radius, half
        real(wp) :: margin

        m = (stress(1) + stress(2) + stress(3))/3.0_wp
        b = stress(1:3) - m
        sxy = stress(4)
        syz = 0.0_wp
        szx = 0.0_wp
        if (size(stress) == 6) then
            syz = stress(5)
            szx = stress(6)
        end if
        scale = max(maxval(abs(stress)), 2.0_wp*cohesion*cos(friction), sqrt(tiny(1.0_wp)))
        if (cutoff) scale = max(scale, abs(tension))
        margin = margin_factor*scale
        if (size(stress) == 4) then
            ! plane strain: the in-plane pair from the circle, the out-of-plane value apart
            half = 0.5_wp*(stress(1) - stress(2))
            radius = sqrt(half*half + sxy*sxy)
            s1 = max(0.5_wp*(stress(1) + stress(2)) + radius, stress(3))
            s3 = min(0.5_wp*(stress(1) + stress(2)) - radius, stress(3))
        else
            j2 = 0.5_wp*sum(b**2) + sxy**2 + syz**2 + szx**2
            if (j2 <= 0.0_wp) then
                s1 = m
                s3 = m
            else
                radius = sqrt(j2/3.0_wp)
                ! r = det(deviator / radius) / 2, in [-1, 1] up to round-off
                r = (b(1)*(b(2)*b(3) - syz*syz) - sxy*(sxy*b(3) - syz*szx) &
                    + szx*(sxy*syz - b(2)*szx))/(2.0_wp*radius**3)
                angle = acos(max(-1.0_wp, min(1.0_wp, r)))/3.0_wp
                s1 = m + 2.0_wp*radius*cos(angle)
                s3 = m + 2.0_wp*radius*cos(angle + third_turn)
            end if
        end if
        clearly_elastic = (s1 - s3) + (s1 + s3)*sin(friction) - 2.0_wp*cohesion*cos(friction) &
            < -margin
        if (cutoff) clearly_elastic = clearly_elastic .and. s1 - tension < -margin
    end function clearly_elastic

    !> Return of ordered principal stresses s1 >= s2 >= s3 to the pyramid and the cut-off.
    !>
    !> See the module documentation for the planes and the order of the candidates.
    pure subroutine principal_return(s, friction, cohesion, dilatancy, tension, cutoff, shear, &
            lame, plastic)
        real(wp), intent(inout) :: s(3)
            !! trial principal stresses, ordered s1 >= s2 >= s3, on exit the returned ones [Pa]
        real(wp), intent(in) :: friction
            !! friction angle phi [rad]
        real(wp), intent(in) :: cohesion
            !! cohesion c [Pa]
        real(wp), intent(in) :: dilatancy
            !! dilatancy angle psi [rad]
        real(wp), intent(in) :: tension
            !! tensile strength sigma_t (used when `cutoff`) [Pa]
        logical, intent(in) :: cutoff
            !! whether the cut-off planes are part of the surface
        real(wp), intent(in) :: shear
            !! shear modulus G [Pa]
        real(wp), intent(in) :: lame
            !! first Lame parameter lambda [Pa]
        logical, intent(out) :: plastic
            !! whether the stress was returned

        real(wp) :: sphi, cphi, spsi, k, scale, yield
        real(wp) :: a(3, 6), r(3, 6), rhs(6), trial(3), best(3), sc(3), dl(3), m(3, 3)
        real(wp) :: violation, best_violation
        integer :: ic, n, i, j, nplanes
        integer :: act(3)
        logical :: ok

        sphi = sin(friction)
        cphi = cos(friction)
        spsi = sin(dilatancy)
        k = 2.0_wp*cohesion*cphi
        ! the floor (1e-154 Pa) keeps the tolerances normal numbers for a zero stress
        scale = max(maxval(abs(s)), k, sqrt(tiny(1.0_wp)))
        if (cutoff) scale = max(scale, abs(tension))

        yield = mohr_coulomb_yield(s, sphi, k)
        plastic = yield > tol_yield*scale
        if (cutoff) plastic = plastic .or. s(1) - tension > tol_yield*scale
        if (.not. plastic) return

        ! outward normals a_i, plane constants rhs_i (a_i . s = rhs_i on the plane) and the
        ! return directions r_i = D b_i = 2 G b_i + lambda tr(b_i) (1, 1, 1)
        a(:, plane_a) = [1.0_wp + sphi, 0.0_wp, -(1.0_wp - sphi)]
        a(:, plane_b) = [1.0_wp + sphi, -(1.0_wp - sphi), 0.0_wp]
        a(:, plane_c) = [0.0_wp, 1.0_wp + sphi, -(1.0_wp - sphi)]
        r(:, plane_a) = [1.0_wp + spsi, 0.0_wp, -(1.0_wp - spsi)]
        r(:, plane_b) = [1.0_wp + spsi, -(1.0_wp - spsi), 0.0_wp]
        r(:, plane_c) = [0.0_wp, 1.0_wp + spsi, -(1.0_wp - spsi)]
        a(:, plane_t1:plane_t3) = 0.0_wp
        a(1, plane_t1) = 1.0_wp
        a(2, plane_t2) = 1.0_wp
        a(3, plane_t3) = 1.0_wp
        r(:, plane_t1:plane_t3) = a(:, plane_t1:plane_t3)
        do j = 1, 6
            r(:, j) = 2.0_wp*shear*r(:, j) + lame*sum(r(:, j))
        end do
        rhs(plane_a:plane_c) = k
        rhs(plane_t1:plane_t3) = tension

        trial = s
        best = s
        best_violation = huge(1.0_wp)
        nplanes = merge(6, 3, cutoff)
        do ic = 1, ncandidates
            act = candidates(:, ic)
            n = count(act > 0)
            if (any(act(1:n) > nplanes)) cycle
            do j = 1, n
                do i = 1, n
                    m(i, j) = dot_product(a(:, act(i)), r(:, act(j)))
                end do
                dl(j) = dot_product(a(:, act(j)), trial) - rhs(act(j))
            end do
            call solve_small(m, dl, n, ok)
            if (.not. ok) cycle
            sc = trial
            do j = 1, n
                sc = sc - dl(j)*r(:, act(j))
            end do
            ! violation (relative to the stress scale): negative multipliers, lost order,
            ! a violated Mohr-Coulomb plane (any ordering) or cut-off
            violation = max(0.0_wp, sc(2) - sc(1), sc(3) - sc(2), &
                mohr_coulomb_yield(sc, sphi, k))
            do j = 1, n
                violation = max(violation, -dl(j)*maxval(abs(r(:, act(j)))))
            end do
            if (cutoff) violation = max(violation, maxval(sc) - tension)
            violation = violation/scale
            if (violation <= tol_candidate) then
                s = sc
                return
            end if
            if (violation < best_violation) then
                best_violation = violation
                best = sc
            end if
        end do

        if (.not. cutoff .and. has_apex(sphi, cohesion, cphi)) then
            ! what no face or edge accepts returns to the apex
            s = cohesion*cphi/sphi
        else
            ! only reached at region boundaries through round-off: the least violating one
            s = best
        end if
    end subroutine principal_return

    !> Mohr-Coulomb yield function of three principal stresses in any order [Pa].
    pure real(wp) function mohr_coulomb_yield(s, sphi, k)
        real(wp), intent(in) :: s(3)
            !! principal stresses [Pa]
        real(wp), intent(in) :: sphi
            !! sin(phi) [-]
        real(wp), intent(in) :: k
            !! 2 c cos(phi) [Pa]
        mohr_coulomb_yield = (maxval(s) - minval(s)) + (maxval(s) + minval(s))*sphi - k
    end function mohr_coulomb_yield

    !> Solve m x = b in place for n <= 3 by Gaussian elimination with partial pivoting.
    pure subroutine solve_small(m, b, n, ok)
        real(wp), intent(inout) :: m(3, 3)
            !! the n x n matrix in m(1:n, 1:n), destroyed
        real(wp), intent(inout) :: b(3)
            !! right-hand side in b(1:n), on exit the solution
        integer, intent(in) :: n
            !! size of the system
        logical, intent(out) :: ok
            !! false when the matrix is singular to working precision

        ! fixed-size arguments and scratch: no array temporaries (heap) per call
        integer :: i, j, piv
        real(wp) :: factor, tmp(3), big, t

        big = maxval(abs(m(1:n, 1:n)))
        ok = big > 0.0_wp
        if (.not. ok) return
        do j = 1, n
            piv = j - 1 + maxloc(abs(m(j:n, j)), dim=1)
            if (abs(m(piv, j)) <= epsilon(1.0_wp)*big) then
                ok = .false.
                return
            end if
            if (piv /= j) then
                tmp(1:n) = m(j, 1:n)
                m(j, 1:n) = m(piv, 1:n)
                m(piv, 1:n) = tmp(1:n)
                t = b(j)
                b(j) = b(piv)
                b(piv) = t
            end if
            do i = j + 1, n
                factor = m(i, j)/m(j, j)
                m(i, j:n) = m(i, j:n) - factor*m(j, j:n)
                b(i) = b(i) - factor*b(j)
            end do
        end do
        do j = n, 1, -1
            b(j) = (b(j) - dot_product(m(j, j + 1:n), b(j + 1:n)))/m(j, j)
        end do
    end subroutine solve_small

    !> Principal stresses of a plane-strain stress (xx yy zz xy): the in-plane major and minor
    !> values, then s_zz, with the direction of the major one as cos and sin of twice its angle.
    pure subroutine principal_plane(stress, p, cos2, sin2)
        real(wp), intent(in) :: stress(4)
            !! stress xx yy zz xy [Pa]
        real(wp), intent(out) :: p(3)
            !! in-plane major, in-plane minor, zz principal stress [Pa]
        real(wp), intent(out) :: cos2
            !! cos(2 theta), theta the angle of the major direction from x [-]
        real(wp), intent(out) :: sin2
            !! sin(2 theta) [-]

        real(wp) :: centre, half, radius

        centre = 0.5_wp*(stress(1) + stress(2))
        half = 0.5_wp*(stress(1) - stress(2))
        radius = sqrt(half*half + stress(4)*stress(4))
        if (radius > 0.0_wp) then
            cos2 = half/radius
            sin2 = stress(4)/radius
        else
            ! isotropic in the plane: any direction is principal
            cos2 = 1.0_wp
            sin2 = 0.0_wp
        end if
        p = [centre + radius, centre - radius, stress(3)]
    end subroutine principal_plane

    !> Eigenvalues and orthonormal eigenvectors of a symmetric 3x3 stress (cyclic Jacobi).
    !>
    !> Each rotation zeroes one off-diagonal entry exactly and the others shrink quadratically;
    !> an entry below 1e-2 epsilon of its diagonal pair is set to zero (it moves the eigenvalues
    !> by less than that), so the sweeps end with a diagonal matrix after a few passes, also
    !> for repeated eigenvalues, where no rotation is needed.
    pure subroutine symmetric_eigen(s, lam, vec)
        real(wp), intent(in) :: s(6)
            !! symmetric tensor, Voigt xx yy zz xy yz zx [Pa]
        real(wp), intent(out) :: lam(3)
            !! eigenvalues, unordered [Pa]
        real(wp), intent(out) :: vec(3, 3)
            !! eigenvectors, column k for lam(k) [-]

        integer, parameter :: max_sweeps = 50
        real(wp), parameter :: negligible = 1.0e-2_wp*epsilon(1.0_wp)
        real(wp) :: a(3, 3), apq, theta, t, c, sn, tau, g, h
        integer :: sweep, ip, iq, ir

        a = voigt_matrix(s)
        vec = 0.0_wp
        vec(1, 1) = 1.0_wp
        vec(2, 2) = 1.0_wp
        vec(3, 3) = 1.0_wp
        do sweep = 1, max_sweeps
            if (a(1, 2) == 0.0_wp .and. a(1, 3) == 0.0_wp .and. a(2, 3) == 0.0_wp) exit
            do ip = 1, 2
                do iq = ip + 1, 3
                    apq = a(ip, iq)
                    if (apq == 0.0_wp) cycle
                    if (abs(apq) <= negligible*(abs(a(ip, ip)) + abs(a(iq, iq)))) then
                        a(ip, iq) = 0.0_wp
                        a(iq, ip) = 0.0_wp
                        cycle
                    end if
                    ! rotation angle (Numerical Recipes, jacobi); |theta| < 1e19 by the test above
                    theta = (a(iq, iq) - a(ip, ip))/(2.0_wp*apq)
                    t = sign(1.0_wp, theta)/(abs(theta) + sqrt(1.0_wp + theta*theta))
                    c = 1.0_wp/sqrt(1.0_wp + t*t)
                    sn = t*c
                    tau = sn/(1.0_wp + c)
                    a(ip, ip) = a(ip, ip) - t*apq
                    a(iq, iq) = a(iq, iq) + t*apq
                    a(ip, iq) = 0.0_wp
                    a(iq, ip) = 0.0_wp
                    do ir = 1, 3
                        if (ir == ip .or. ir == iq) cycle
                        g = a(ir, ip)
                        h = a(ir, iq)
                        a(ir, ip) = g - sn*(h + g*tau)
                        a(ip, ir) = a(ir, ip)
                        a(ir, iq) = h + sn*(g - h*tau)
                        a(iq, ir) = a(ir, iq)
                    end do
                    do ir = 1, 3
                        g = vec(ir, ip)
                        h = vec(ir, iq)
                        vec(ir, ip) = g - sn*(h + g*tau)
                        vec(ir, iq) = h + sn*(g - h*tau)
                    end do
                end do
            end do
        end do
        lam = [a(1, 1), a(2, 2), a(3, 3)]
    end subroutine symmetric_eigen

    !> Indices that order three values from the largest to the smallest.
    pure function descending_order(p) result(order)
        real(wp), intent(in) :: p(3)
            !! values [any unit]
        integer :: order(3)
            !! p(order) is non-increasing

        integer :: tmp

        order = [1, 2, 3]
        if (p(order(2)) > p(order(1))) order([1, 2]) = order([2, 1])
        if (p(order(3)) > p(order(2))) then
            tmp = order(3)
            order(3) = order(2)
            order(2) = tmp
            if (p(order(2)) > p(order(1))) order([1, 2]) = order([2, 1])
        end if
    end function descending_order

end module mpm_material_mohr_coulomb
