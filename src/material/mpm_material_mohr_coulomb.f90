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
!> plane in principal stress space and linear elasticity is isotropic): the principal values
!> of the trial stress come in closed form (2D plane strain: the in-plane 2x2 plus s_zz; 3D:
!> the trigonometric solution of the characteristic cubic of the deviator), computed once
!> for a test that spares most elastic stresses the rest and for the return; they are
!> ordered and returned in principal space as a multi-surface problem,
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
!> (sigma_t, sigma_t, sigma_t); the two edges swap places when the return to the face A
!> leaves s2 > s1 (the compression side, where most returns of a granular flow end). A
!> candidate is accepted when all its multipliers are non-negative, its stress stays ordered
!> and it violates no other plane (to round-off).
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
!> The first candidate, the face A alone (the most frequent single plane), is solved in
!> closed form; the planes and the factorised systems of the others depend only on the
!> strength and are computed once by the constructor (without softening).
!>
!> The returned principal values rebuild the stress as a correction
!> sigma_trial - sum_k (s_k,trial - s_k) P_k, P_k the eigenprojectors of the trial stress:
!> in 2D from the direction of the in-plane pair; in 3D, where the principal values are more
!> than 1e-3 of the largest stress component apart, from the spectral projectors
!> P_k = prod_(i /= k) (sigma - s_i I) / (s_k - s_i), without eigenvectors, after one
!> Rayleigh-quotient refinement of the trigonometric values of the closer pair
!> (`well_separated` gives the error analysis: exact to a few eps |sigma|); where two of them
!> are closer, from the eigenvectors n_k of cyclic Jacobi rotations (P_k = n_k n_k^T, to
!> round-off, robust for repeated eigenvalues).
!>
!> Softening: phi, c and psi follow the accumulated plastic shear strain eps_q, taken at the
!> start of the step (explicit in the hardening variable, so each step is a return to fixed
!> planes: simple, exact for the step and stable for the small steps of explicit MPM).
!> The planes of a step (sin(phi), cos(phi), sin(psi), 2 c cos(phi), sigma_t) are evaluated
!> once: by the constructor for a constant strength, once per update with softening.
!>
!> State of a particle: state(1) = accumulated equivalent plastic shear strain
!> eps_q = sum sqrt(2/3 de_p : de_p) (de_p the deviatoric plastic strain increment) [-],
!> state(2) = accumulated plastic volumetric strain, tension positive (dilation > 0) [-].
!>
!> With `separation` (see `mpm_separation`), state(3) = opening strain [-].
!>
!> `materials[i].type = "mohr_coulomb"`: keys `E`, `nu`, `rho` (`mpm_elastic_solid`) and the
!> strength (`mpm_strength`).
module mpm_material_mohr_coulomb
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    use mpm_softening, only: softened_strength, softening_none
    use mpm_separation, only: close_opening
    use mpm_material, only: material_key_width, work_plastic, update_each, material_chunk, chunk_in
    use mpm_elastic_solid, only: elastic_solid_type, elastic_keys
    use mpm_strength, only: strength_type, read_strength, strength_keys, strength_section_keys, &
        strength_summary, reduced_strength
    use mpm_stress, only: add_jaumann_rotation, voigt_matrix
    implicit none
    private
    public :: mohr_coulomb_material_type, new_mohr_coulomb_material, &
        mohr_coulomb_principal_return, mohr_coulomb_return_chunk_3d

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
    !> The extension and compression edges in `candidates`.
    integer, parameter :: edge_ab = 3, edge_ac = 4
    !> Relative round-off allowed in the yield check and in the tests of a candidate [-].
    real(wp), parameter :: tol_yield = 16.0_wp*epsilon(1.0_wp)
    real(wp), parameter :: tol_candidate = 64.0_wp*epsilon(1.0_wp)

    !> The planes of one step: the strength with the trigonometric values the return uses.
    type :: mohr_coulomb_surface_type
        real(wp) :: sin_friction = 0.0_wp
            !! sin(phi) [-]
        real(wp) :: cos_friction = 1.0_wp
            !! cos(phi) [-]
        real(wp) :: sin_dilatancy = 0.0_wp
            !! sin(psi) [-]
        real(wp) :: k = 0.0_wp
            !! 2 c cos(phi), the constant of the Mohr-Coulomb planes [Pa]
        real(wp) :: tension = huge(1.0_wp)
            !! tensile strength sigma_t (when `cutoff`; else the apex c cot(phi), or huge for
            !! phi = 0) [Pa]
        logical :: cutoff = .false.
            !! whether the tension cut-off planes cut the pyramid below its apex
        logical :: apex = .false.
            !! whether the pyramid has a finite apex c cot(phi) (`has_apex`)
    end type mohr_coulomb_surface_type

    !> The planes of the return in principal space and the systems a_i . D b_j of the candidate
    !> sets, factorised; constant for a constant strength (computed once by the constructor).
    !> No default initialisation: a local one costs nothing until it is filled.
    type :: return_planes_type
        real(wp) :: a(3, 6)
            !! outward normals a_i of the planes A, B, C, T1, T2, T3 [-]
        real(wp) :: r(3, 6)
            !! return directions r_i = D b_i = 2 G b_i + lambda tr(b_i) (1, 1, 1) [Pa]
        real(wp) :: rhs(6)
            !! plane constants, a_i . s = rhs_i on plane i [Pa]
        real(wp) :: rmax(6)
            !! largest absolute component of each r_i [Pa]
        integer :: nactive(ncandidates)
            !! planes of each candidate; 0: not available (cut-off planes without a cut-off)
            !! or, when `factorised`, singular to working precision
        logical :: factorised
            !! whether `lu` and `pivot` hold the factorised systems (else built per candidate)
        real(wp) :: lu(3, 3, ncandidates)
            !! LU factors of a_i . r_j of each candidate, multipliers below the diagonal [Pa]
        integer :: pivot(3, ncandidates)
            !! row exchanged with row j at step j of each factorisation
    end type return_planes_type

    !> The principal values of a 3D trial stress between return_3d's steps (principal_values_3d,
    !> then the return, then correct_stress_3d).
    type :: principal_3d_type
        logical :: spectral
            !! the values are well apart: spectral projectors (b, off, values), else the
            !! principal directions (vec, order)
        real(wp) :: b(3), off(3), values(3)
            !! deviatoric diagonal and off-diagonal of the trial stress, refined deviatoric
            !! principal values [Pa]
        real(wp) :: p(3)
            !! principal trial stresses (of the eigen-decomposition, in its order) [Pa]
        real(wp) :: vec(3, 3)
            !! principal directions (columns)
        integer :: order(3)
            !! descending order of p
    end type principal_3d_type

    !> Mohr-Coulomb with tension cut-off, non-associated flow and softening; E, nu, rho, G and
    !> lambda come from `elastic_solid_type`.
    type, extends(elastic_solid_type) :: mohr_coulomb_material_type
        type(strength_type) :: strength
            !! friction, cohesion, dilatancy, tension cut-off (largest principal stress
            !! allowed; negative: not given, the apex limits it), softening and separation
        type(mohr_coulomb_surface_type) :: peak
            !! the planes of the peak strength, set by the constructor (all of the surface
            !! without softening)
        type(return_planes_type) :: peak_planes
            !! the return planes and factorised candidate systems of the peak strength, set by
            !! the constructor (used without softening); `peak` and `peak_planes` derive from
            !! the components above, so a material is made by `new_mohr_coulomb_material`
        logical :: jacobi_only = .false.
            !! 3D: always the Jacobi eigen-decomposition (the reference of the tests; slower)
    contains
        procedure, nopass :: names => mohr_coulomb_names
        procedure, nopass :: keys => mohr_coulomb_keys
        procedure, nopass :: section_keys => strength_section_keys
        procedure :: read => mohr_coulomb_read
        procedure :: writes_plastic_strain => mohr_coulomb_writes_plastic_strain
        procedure :: summary => mohr_coulomb_summary
        procedure :: update_stress => mohr_coulomb_update_stress
            !! exact return mapping of one particle over one step
        procedure :: update_stress_block => mohr_coulomb_update_stress_block
            !! the same for a block: predictor, principal values and elastic test vectorised
        procedure :: nstate => mohr_coulomb_nstate
            !! two state values: eps_q and the plastic volumetric strain
        procedure :: strength_after => mohr_coulomb_strength
            !! phi, c, psi and the tensile strength after a given plastic shear strain
        procedure :: work_kind => mohr_coulomb_work_kind
            !! plastic: the work beyond the stored elastic energy is dissipated
        !> K0 after Jaky (1944): 1 - sin(phi), of the peak friction angle.
        procedure :: at_rest_ratio => mohr_coulomb_at_rest_ratio
        procedure :: reduce_strength => mohr_coulomb_reduce_strength
            !! tan(phi), c and the tensile strength divided by F (`reduced_strength`)
    end type mohr_coulomb_material_type

contains

    !> Where the work of the stresses goes: plastic dissipation beyond the stored part.
    !> K0 of a normally consolidated soil after Jaky (1944): 1 - sin(phi), phi the peak
    !> friction angle.
    pure real(wp) function mohr_coulomb_at_rest_ratio(self)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material

        mohr_coulomb_at_rest_ratio = 1.0_wp - sin(self%strength%friction)
    end function mohr_coulomb_at_rest_ratio

    !> Strength reduction: the strength divided by F (`mpm_strength::reduced_strength`).
    pure subroutine mohr_coulomb_reduce_strength(self, factor, reduced)
        class(mohr_coulomb_material_type), intent(inout) :: self
            !! the material
        real(wp), intent(in) :: factor
            !! strength reduction factor F > 0 [-]
        logical, intent(out) :: reduced
            !! whether it has a strength to reduce (it has)

        call set_up(self, reduced_strength(self%strength, factor))
        reduced = .true.
    end subroutine mohr_coulomb_reduce_strength

    pure integer function mohr_coulomb_work_kind(self)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        mohr_coulomb_work_kind = work_plastic
    end function mohr_coulomb_work_kind

    !> Names accepted for `type`.
    pure subroutine mohr_coulomb_names(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=material_key_width) :: "mohr_coulomb"]
    end subroutine mohr_coulomb_names

    !> Keys of a Mohr-Coulomb material.
    pure subroutine mohr_coulomb_keys(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=material_key_width) :: elastic_keys, strength_keys]
    end subroutine mohr_coulomb_keys

    !> Elasticity (`E`, `nu`, `rho`), then strength (mpm_strength).
    subroutine mohr_coulomb_read(self, item, error)
        class(mohr_coulomb_material_type), intent(inout) :: self
            !! the material
        type(cursor_type), intent(in) :: item
            !! the material object ("materials[i]")
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(strength_type) :: strength

        call self%read_elasticity(item, error)
        if (allocated(error)) return
        call read_strength(item, "Mohr-Coulomb", strength, error)
        if (allocated(error)) return
        call set_up(self, strength)
    end subroutine mohr_coulomb_read

    !> The plastic shear strain is the state this material writes.
    pure logical function mohr_coulomb_writes_plastic_strain(self)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material

        mohr_coulomb_writes_plastic_strain = .true.
    end function mohr_coulomb_writes_plastic_strain

    !> The elastic line, then the strength.
    pure subroutine mohr_coulomb_summary(self, text)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        character(len=:), allocatable, intent(out) :: text
            !! the lines

        call self%elasticity_summary(text)
        text = text//strength_summary(self%strength, "")
    end subroutine mohr_coulomb_summary

    !> Construct a Mohr-Coulomb material from E, nu, rho and its strength.
    pure subroutine new_mohr_coulomb_material(mat, young, poisson, density, strength)
        type(mohr_coulomb_material_type), intent(out) :: mat
            !! the material
        real(wp), intent(in) :: young
            !! Young's modulus [Pa]
        real(wp), intent(in) :: poisson
            !! Poisson's ratio [-]
        real(wp), intent(in) :: density
            !! mass density [kg/m3]
        type(strength_type), intent(in) :: strength
            !! friction, cohesion, dilatancy, cut-off, softening, separation

        call mat%set_elasticity(young, poisson, density)
        call set_up(mat, strength)
    end subroutine new_mohr_coulomb_material

    !> Strength of a material whose elasticity is set, and the planes of its peak strength.
    pure subroutine set_up(mat, strength)
        class(mohr_coulomb_material_type), intent(inout) :: mat
            !! the material
        type(strength_type), intent(in) :: strength
            !! its strength

        mat%strength = strength
        mat%peak = mohr_coulomb_surface(strength%friction, strength%cohesion, &
            strength%dilatancy, strength%tension_cutoff)
        call new_return_planes(mat%peak_planes, mat%peak, mat%shear, mat%lame, factorise=.true.)
    end subroutine set_up

    !> Two state values per particle, eps_q and the plastic volumetric strain, and with
    !> separation a third, the opening strain.
    pure integer function mohr_coulomb_nstate(self)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        mohr_coulomb_nstate = merge(3, 2, self%strength%separation)
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

        type(mohr_coulomb_surface_type) :: surface

        call softened_surface(self, eps_q, surface, friction, cohesion, dilatancy)
        tension = surface%tension
        cutoff = surface%cutoff
    end subroutine mohr_coulomb_strength

    !> The planes of the strength after the plastic shear strain eps_q, with its friction,
    !> cohesion and dilatancy (see `mohr_coulomb_strength`).
    pure subroutine softened_surface(self, eps_q, surface, friction, cohesion, dilatancy)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: eps_q
            !! accumulated equivalent plastic shear strain [-]
        type(mohr_coulomb_surface_type), intent(out) :: surface
            !! the planes
        real(wp), intent(out) :: friction
            !! friction angle phi [rad]
        real(wp), intent(out) :: cohesion
            !! cohesion c [Pa]
        real(wp), intent(out) :: dilatancy
            !! dilatancy angle psi [rad]

        associate (s => self%strength)
            call softened_strength(s%softening, s%softening_strain, eps_q, &
                [s%friction, s%cohesion, s%dilatancy], &
                [s%friction_residual, s%cohesion_residual, s%dilatancy_residual], &
                friction, cohesion, dilatancy)
            surface = mohr_coulomb_surface(friction, cohesion, dilatancy, s%tension_cutoff)
        end associate
    end subroutine softened_surface

    !> The planes of a strength: sin(phi), cos(phi), sin(psi), k = 2 c cos(phi) and the tensile
    !> strength min(tension_cutoff, c cot(phi)), each trigonometric function evaluated once.
    pure function mohr_coulomb_surface(friction, cohesion, dilatancy, tension_cutoff) &
            result(surface)
        real(wp), intent(in) :: friction
            !! friction angle phi [rad]
        real(wp), intent(in) :: cohesion
            !! cohesion c [Pa]
        real(wp), intent(in) :: dilatancy
            !! dilatancy angle psi [rad]
        real(wp), intent(in) :: tension_cutoff
            !! largest principal stress allowed [Pa]; negative: not given
        type(mohr_coulomb_surface_type) :: surface
            !! the planes

        real(wp) :: sphi, cphi

        sphi = sin(friction)
        cphi = cos(friction)
        surface%sin_friction = sphi
        surface%cos_friction = cphi
        surface%sin_dilatancy = sin(dilatancy)
        surface%k = 2.0_wp*cohesion*cphi
        surface%apex = has_apex(sphi, cohesion, cphi)
        ! sigma_t < c cot(phi) written without the division (phi may be 0)
        surface%cutoff = tension_cutoff >= 0.0_wp .and. tension_cutoff*sphi < cohesion*cphi
        if (surface%cutoff) then
            surface%tension = tension_cutoff
        else if (surface%apex) then
            surface%tension = cohesion*cphi/sphi
        else
            surface%tension = huge(1.0_wp)
        end if
    end function mohr_coulomb_surface

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

        type(mohr_coulomb_surface_type) :: surface
        real(wp) :: friction, cohesion, dilatancy, dvol, de(6)
        integer :: n
        real(wp) :: p(3), radius
        real(wp) :: m, b(3), off(3), mu(3), s1, s3, magnitude
        logical :: open

        if (self%strength%softening == softening_none) then
            surface = self%peak
        else
            call softened_surface(self, state(1), surface, friction, cohesion, dilatancy)
        end if

        n = size(dstrain)
        de(1:n) = dstrain
        if (self%strength%separation) then
            call close_opening(de(1:n), state(3), state(1), open)
            if (open) then
                stress = 0.0_wp
                return
            end if
        end if
        ! mpm_elastic_solid::add_elastic_trial written out: with the call, the optimiser
        ! compiled the 3D update otherwise and its cases changed in the last bits
        dvol = de(1) + de(2) + de(3)
        call add_jaumann_rotation(stress, omega)
        stress = stress + 2.0_wp*self%shear*de(1:n)
        stress(1:3) = stress(1:3) + self%lame*dvol

        ! principal values in closed form, once, for the elastic test and the return (2D: the
        ! circle in the plane and s_zz; 3D: the trigonometric solution of the characteristic
        ! cubic of the deviator, mu sorted in descending order)
        if (n == 4) then
            call principal_plane(stress, p, radius)
            s1 = max(p(1), p(3))
            s3 = min(p(2), p(3))
        else
            m = (stress(1) + stress(2) + stress(3))/3.0_wp
            b = stress(1:3) - m
            off = stress(4:6)
            call deviator_eigenvalues(b, off, mu)
            s1 = m + mu(1)
            s3 = m + mu(3)
        end if
        magnitude = maxval(abs(stress))
        ! stresses clearly inside the surface need no eigen-decomposition and no return
        if (clearly_elastic(s1, s3, magnitude, surface)) return

        if (n == 6) then
            call return_3d(self, surface, stress, state, m, mu, magnitude)
        else
            call return_2d(self, surface, stress, state, p, radius)
        end if
    end subroutine mohr_coulomb_update_stress

    include "mpm_mohr_coulomb_block.inc"

    !> The return of a 3D trial stress that may yield, from its mean and deviatoric principal
    !> values (deviator_eigenvalues): spectral projectors where the values are well apart,
    !> else the principal directions of Jacobi's method (see the module documentation).
    pure subroutine return_3d(self, surface, stress, state, m, mu, magnitude)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        type(mohr_coulomb_surface_type), intent(in) :: surface
            !! the planes of the step
        real(wp), intent(inout) :: stress(:)
            !! the trial stress (6), on exit the returned one [Pa]
        real(wp), intent(inout) :: state(:)
            !! state of the particle
        real(wp), intent(in) :: m
            !! mean trial stress [Pa]
        real(wp), intent(in) :: mu(3)
            !! deviatoric principal values of the trial stress [Pa]
        real(wp), intent(in) :: magnitude
            !! largest absolute component of the trial stress [Pa]

        type(principal_3d_type) :: pr
        real(wp) :: ps(3)
        logical :: plastic

        call principal_values_3d(self, stress, m, mu, magnitude, pr, ps)
        call return_to_surface(self, ps, surface, plastic)
        if (plastic) call correct_stress_3d(self, pr, ps, stress, state)
    end subroutine return_3d

    !> The principal trial stresses of return_3d, ordered s1 >= s2 >= s3, and what the
    !> correction needs afterwards: with the values well apart, the refined values and the
    !> deviator (spectral projectors); else the principal directions of Jacobi's method.
    pure subroutine principal_values_3d(self, stress, m, mu, magnitude, pr, ps)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: stress(:)
            !! the trial stress (6) [Pa]
        real(wp), intent(in) :: m
            !! mean trial stress [Pa]
        real(wp), intent(in) :: mu(3)
            !! deviatoric principal values of the trial stress [Pa]
        real(wp), intent(in) :: magnitude
            !! largest absolute component of the trial stress [Pa]
        type(principal_3d_type), intent(out) :: pr
            !! the principal values and what the correction needs
        real(wp), intent(out) :: ps(3)
            !! the principal trial stresses, ordered [Pa]

        pr%spectral = .false.
        if (.not. self%jacobi_only) then
            pr%values = mu
            if (well_separated(pr%values, magnitude)) then
                ! distinct principal values: spectral projectors, no eigenvectors
                pr%spectral = .true.
                pr%b = stress(1:3) - m
                pr%off = stress(4:6)
                call refine_pair(pr%b, pr%off, pr%values)
                pr%p = m + pr%values
                ps = pr%p
                return
            end if
        end if
        ! two principal values close (or `jacobi_only`): principal directions
        call symmetric_eigen(stress(1:6), pr%p, pr%vec)
        pr%order = descending_order(pr%p)
        ps = pr%p(pr%order)
    end subroutine principal_values_3d

    !> The stress and state after a 3D return to the principal stresses ps (principal_values_3d
    !> gave the trial ones): the correction of each principal value, then the plastic strain.
    pure subroutine correct_stress_3d(self, pr, ps, stress, state)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        type(principal_3d_type), intent(in) :: pr
            !! the trial principal values (principal_values_3d)
        real(wp), intent(in) :: ps(3)
            !! the returned principal stresses, ordered [Pa]
        real(wp), intent(inout) :: stress(:)
            !! the trial stress (6), on exit the returned one [Pa]
        real(wp), intent(inout) :: state(:)
            !! state of the particle

        real(wp) :: dp(3)

        if (pr%spectral) then
            dp = pr%p - ps
            call spectral_correction(stress, pr%b, pr%off, pr%values, dp)
        else
            ! correction of each principal value, in the order of the eigen-decomposition
            dp(pr%order) = pr%p(pr%order) - ps
            stress(1) = stress(1) - sum(dp*pr%vec(1, :)**2)
            stress(2) = stress(2) - sum(dp*pr%vec(2, :)**2)
            stress(3) = stress(3) - sum(dp*pr%vec(3, :)**2)
            stress(4) = stress(4) - sum(dp*pr%vec(1, :)*pr%vec(2, :))
            stress(5) = stress(5) - sum(dp*pr%vec(2, :)*pr%vec(3, :))
            stress(6) = stress(6) - sum(dp*pr%vec(3, :)*pr%vec(1, :))
        end if
        call add_plastic_strain(self, dp, ps, pr%p, stress, state)
    end subroutine correct_stress_3d

    !> The return of a plane-strain trial stress that may yield, from its principal values
    !> (principal_plane), the correction in the direction of the in-plane pair.
    pure subroutine return_2d(self, surface, stress, state, p, radius)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        type(mohr_coulomb_surface_type), intent(in) :: surface
            !! the planes of the step
        real(wp), intent(inout) :: stress(:)
            !! the trial stress (4), on exit the returned one [Pa]
        real(wp), intent(inout) :: state(:)
            !! state of the particle
        real(wp), intent(in) :: p(3)
            !! in-plane major, in-plane minor and zz trial principal stresses [Pa]
        real(wp), intent(in) :: radius
            !! radius of Mohr's circle in the plane [Pa]

        real(wp) :: ps(3)
        integer :: order(3)
        logical :: plastic

        order = descending_order(p)
        ps = p(order)
        call return_to_surface(self, ps, surface, plastic)
        if (plastic) call correct_stress_2d(self, p, order, ps, radius, stress, state)
    end subroutine return_2d

    !> The stress and state after a plane-strain return to the principal stresses ps: the
    !> correction in the direction of the in-plane pair, then the plastic strain.
    pure subroutine correct_stress_2d(self, p, order, ps, radius, stress, state)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: p(3)
            !! in-plane major, in-plane minor and zz trial principal stresses [Pa]
        integer, intent(in) :: order(3)
            !! their descending order
        real(wp), intent(in) :: ps(3)
            !! the returned principal stresses, ordered [Pa]
        real(wp), intent(in) :: radius
            !! radius of Mohr's circle in the plane [Pa]
        real(wp), intent(inout) :: stress(:)
            !! the trial stress (4), on exit the returned one [Pa]
        real(wp), intent(inout) :: state(:)
            !! state of the particle

        real(wp) :: dp(3), cos2, sin2

        dp(order) = p(order) - ps
        call plane_direction(stress, radius, cos2, sin2)
        stress(1) = stress(1) - 0.5_wp*(dp(1) + dp(2)) - 0.5_wp*(dp(1) - dp(2))*cos2
        stress(2) = stress(2) - 0.5_wp*(dp(1) + dp(2)) + 0.5_wp*(dp(1) - dp(2))*cos2
        stress(3) = stress(3) - dp(3)
        stress(4) = stress(4) - 0.5_wp*(dp(1) - dp(2))*sin2
        call add_plastic_strain(self, dp, ps, p, stress, state)
    end subroutine correct_stress_2d

    !> State after a plastic step: the plastic strain D^-1 (sigma_trial - sigma), coaxial with
    !> the stress, added to eps_q and to the plastic volumetric strain; with separation, a
    !> return to the stress-free apex opens the material by its dilation.
    pure subroutine add_plastic_strain(self, dp, ps, p, stress, state)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: dp(3)
            !! principal values of sigma_trial - sigma, any order [Pa]
        real(wp), intent(in) :: ps(3)
            !! returned principal stresses [Pa]
        real(wp), intent(in) :: p(3)
            !! trial principal stresses [Pa]
        real(wp), intent(inout) :: stress(:)
            !! the returned stress, 4 or 6 components (zero on opening) [Pa]
        real(wp), intent(inout) :: state(:)
            !! state of the particle (see `mohr_coulomb_update_stress`)

        real(wp) :: dev(3), dplastic

        dev = (dp - sum(dp)/3.0_wp)/(2.0_wp*self%shear)
        state(1) = state(1) + sqrt(2.0_wp/3.0_wp*sum(dev**2))
        dplastic = sum(dp)/(3.0_wp*self%lame + 2.0_wp*self%shear)
        state(2) = state(2) + dplastic
        if (self%strength%separation .and. dplastic > 0.0_wp .and. &
            all(abs(ps) <= tol_candidate*maxval(abs(p)))) then
            state(3) = state(3) + dplastic
            stress = 0.0_wp
        end if
    end subroutine add_plastic_strain

    !> Whether a stress is inside the Mohr-Coulomb surface (and the cut-off) by a margin.
    !>
    !> The extreme principal stresses come from closed forms (in 3D the trigonometric solution
    !> of the characteristic cubic, `deviator_eigenvalues`), accurate to about sqrt(epsilon)
    !> of the deviatoric stress where two eigenvalues nearly coincide; the margin (1e-6 of the
    !> stress scale) is far above that, so a stress this test calls elastic is one the return
    !> leaves unchanged, and the eigen-decomposition is spared.
    pure logical function clearly_elastic(s1, s3, magnitude, surface)
        real(wp), intent(in) :: s1
            !! largest principal trial stress [Pa]
        real(wp), intent(in) :: s3
            !! smallest principal trial stress [Pa]
        real(wp), intent(in) :: magnitude
            !! largest absolute component of the trial stress [Pa]
        type(mohr_coulomb_surface_type), intent(in) :: surface
            !! the planes of the step

        real(wp), parameter :: margin_factor = 1.0e-6_wp
        real(wp) :: scale, margin

        scale = max(magnitude, surface%k, sqrt(tiny(1.0_wp)))
        if (surface%cutoff) scale = max(scale, abs(surface%tension))
        margin = margin_factor*scale
        clearly_elastic = (s1 - s3) + (s1 + s3)*surface%sin_friction - surface%k < -margin
        if (surface%cutoff) clearly_elastic = clearly_elastic .and. s1 - surface%tension < -margin
    end function clearly_elastic

    !> `principal_return` with the precomputed planes of the material for a constant strength.
    pure subroutine return_to_surface(self, s, surface, plastic)
        class(mohr_coulomb_material_type), intent(in) :: self
            !! the material
        real(wp), intent(inout) :: s(3)
            !! trial principal stresses, ordered s1 >= s2 >= s3, on exit the returned ones [Pa]
        type(mohr_coulomb_surface_type), intent(in) :: surface
            !! the planes of the step
        logical, intent(out) :: plastic
            !! whether the stress was returned

        if (self%strength%softening == softening_none) then
            call principal_return(s, surface, self%shear, self%lame, plastic, self%peak_planes)
        else
            call principal_return(s, surface, self%shear, self%lame, plastic)
        end if
    end subroutine return_to_surface

    !> Return of ordered principal stresses s1 >= s2 >= s3 to the pyramid and the cut-off.
    !>
    !> See the module documentation for the planes and the order of the candidates.
    pure subroutine principal_return(s, surface, shear, lame, plastic, planes)
        real(wp), intent(inout) :: s(3)
            !! trial principal stresses, ordered s1 >= s2 >= s3, on exit the returned ones [Pa]
        type(mohr_coulomb_surface_type), intent(in) :: surface
            !! the planes of the step
        real(wp), intent(in) :: shear
            !! shear modulus G [Pa]
        real(wp), intent(in) :: lame
            !! first Lame parameter lambda [Pa]
        logical, intent(out) :: plastic
            !! whether the stress was returned
        type(return_planes_type), intent(in), optional :: planes
            !! the planes of `surface`, factorised (constant strength); built here when absent

        type(return_planes_type) :: local
        real(wp) :: sphi, spsi, k, scale, yield
        real(wp) :: trial(3), best(3), sc(3), dl(3), rmax(3), aa(3), ra(3), maa, violation
        real(wp) :: best_violation
        logical :: accepted, compression

        sphi = surface%sin_friction
        spsi = surface%sin_dilatancy
        k = surface%k
        ! the floor (1e-154 Pa) keeps the tolerances normal numbers for a zero stress
        scale = max(maxval(abs(s)), k, sqrt(tiny(1.0_wp)))
        if (surface%cutoff) scale = max(scale, abs(surface%tension))

        yield = mohr_coulomb_yield(s, sphi, k)
        plastic = yield > tol_yield*scale
        if (surface%cutoff) plastic = plastic .or. s(1) - surface%tension > tol_yield*scale
        if (.not. plastic) return

        trial = s
        best = s
        best_violation = huge(1.0_wp)
        compression = .false.

        ! the first candidate, the face A alone, in closed form: dl = (a_A . s - k) /
        ! (a_A . r_A), the same operations as the general solve
        aa = [1.0_wp + sphi, 0.0_wp, -(1.0_wp - sphi)]
        ra = [1.0_wp + spsi, 0.0_wp, -(1.0_wp - spsi)]
        ra = 2.0_wp*shear*ra + lame*sum(ra)
        maa = dot_product(aa, ra)
        if (maa /= 0.0_wp) then
            dl(1) = (dot_product(aa, trial) - k)/maa
            sc = trial - dl(1)*ra
            rmax(1) = maxval(abs(ra))
            violation = candidate_violation(sc, dl, rmax, 1, surface, scale)
            if (violation <= tol_candidate) then
                s = sc
                return
            end if
            best_violation = violation
            best = sc
            ! the face return swapped s1 and s2: the compression edge A+C is the likely one
            compression = sc(2) > sc(1)
        end if

        ! the other candidates, in order
        if (present(planes)) then
            call try_candidates(trial, planes, surface, scale, compression, s, best, &
                best_violation, accepted)
        else
            call new_return_planes(local, surface, shear, lame, factorise=.false.)
            call try_candidates(trial, local, surface, scale, compression, s, best, &
                best_violation, accepted)
        end if
        if (accepted) return

        if (.not. surface%cutoff .and. surface%apex) then
            ! what no face or edge accepts returns to the apex (sigma_t is c cot(phi) there)
            s = surface%tension
        else
            ! only reached at region boundaries through round-off: the least violating one
            s = best
        end if
    end subroutine principal_return

    !> The planes of the return for a strength: outward normals a_i, return directions
    !> r_i = D b_i, plane constants, and (when asked) the factorised systems of the candidates.
    pure subroutine new_return_planes(planes, surface, shear, lame, factorise)
        type(return_planes_type), intent(out) :: planes
            !! the planes
        type(mohr_coulomb_surface_type), intent(in) :: surface
            !! the strength
        real(wp), intent(in) :: shear
            !! shear modulus G [Pa]
        real(wp), intent(in) :: lame
            !! first Lame parameter lambda [Pa]
        logical, intent(in) :: factorise
            !! whether to factorise the systems a_i . r_j of all candidates now

        real(wp) :: sphi, spsi, m(3, 3)
        integer :: ic, n, i, j, nplanes, act(3)
        logical :: ok

        sphi = surface%sin_friction
        spsi = surface%sin_dilatancy
        planes%a(:, plane_a) = [1.0_wp + sphi, 0.0_wp, -(1.0_wp - sphi)]
        planes%a(:, plane_b) = [1.0_wp + sphi, -(1.0_wp - sphi), 0.0_wp]
        planes%a(:, plane_c) = [0.0_wp, 1.0_wp + sphi, -(1.0_wp - sphi)]
        planes%r(:, plane_a) = [1.0_wp + spsi, 0.0_wp, -(1.0_wp - spsi)]
        planes%r(:, plane_b) = [1.0_wp + spsi, -(1.0_wp - spsi), 0.0_wp]
        planes%r(:, plane_c) = [0.0_wp, 1.0_wp + spsi, -(1.0_wp - spsi)]
        planes%a(:, plane_t1:plane_t3) = 0.0_wp
        planes%a(1, plane_t1) = 1.0_wp
        planes%a(2, plane_t2) = 1.0_wp
        planes%a(3, plane_t3) = 1.0_wp
        planes%r(:, plane_t1:plane_t3) = planes%a(:, plane_t1:plane_t3)
        do j = 1, 6
            planes%r(:, j) = 2.0_wp*shear*planes%r(:, j) + lame*sum(planes%r(:, j))
            planes%rmax(j) = maxval(abs(planes%r(:, j)))
        end do
        planes%rhs(plane_a:plane_c) = surface%k
        planes%rhs(plane_t1:plane_t3) = surface%tension

        nplanes = merge(6, 3, surface%cutoff)
        planes%factorised = factorise
        do ic = 1, ncandidates
            act = candidates(:, ic)
            n = count(act > 0)
            if (any(act(1:n) > nplanes)) n = 0
            planes%nactive(ic) = n
            if (.not. factorise .or. n == 0) cycle
            do j = 1, n
                do i = 1, n
                    m(i, j) = dot_product(planes%a(:, act(i)), planes%r(:, act(j)))
                end do
            end do
            call factor_small(m, n, planes%pivot(:, ic), ok)
            planes%lu(:, :, ic) = m
            if (.not. ok) planes%nactive(ic) = 0
        end do
    end subroutine new_return_planes

    !> The candidates after the face A, in order (see the module documentation): the first
    !> one valid to round-off is the return; else the least violating one is kept.
    pure subroutine try_candidates(trial, planes, surface, scale, compression, s, best, &
            best_violation, accepted)
        real(wp), intent(in) :: trial(3)
            !! trial principal stresses, ordered [Pa]
        type(return_planes_type), intent(in) :: planes
            !! the planes of the return
        type(mohr_coulomb_surface_type), intent(in) :: surface
            !! the strength
        real(wp), intent(in) :: scale
            !! stress scale of the tolerances [Pa]
        logical, intent(in) :: compression
            !! try the compression edge A+C before the extension edge A+B (the face return
            !! ended with s2 > s1; most plastic returns of a granular flow end there)
        real(wp), intent(inout) :: s(3)
            !! on acceptance, the returned principal stresses [Pa]
        real(wp), intent(inout) :: best(3)
            !! least violating candidate so far [Pa]
        real(wp), intent(inout) :: best_violation
            !! its violation [-]
        logical, intent(out) :: accepted
            !! whether a candidate was valid

        real(wp) :: m(3, 3), dl(3), sc(3), rmax(3), violation
        integer :: ic, k, n, i, j, act(3), pivot(3)
        logical :: ok

        accepted = .false.
        do k = 2, ncandidates
            ic = k
            if (compression .and. k == edge_ab) ic = edge_ac
            if (compression .and. k == edge_ac) ic = edge_ab
            n = planes%nactive(ic)
            if (n == 0) cycle
            act = candidates(:, ic)
            do j = 1, n
                dl(j) = dot_product(planes%a(:, act(j)), trial) - planes%rhs(act(j))
            end do
            if (planes%factorised) then
                call solve_factored(planes%lu(:, :, ic), planes%pivot(:, ic), dl, n)
            else
                do j = 1, n
                    do i = 1, n
                        m(i, j) = dot_product(planes%a(:, act(i)), planes%r(:, act(j)))
                    end do
                end do
                call factor_small(m, n, pivot, ok)
                if (.not. ok) cycle
                call solve_factored(m, pivot, dl, n)
            end if
            sc = trial
            do j = 1, n
                sc = sc - dl(j)*planes%r(:, act(j))
                rmax(j) = planes%rmax(act(j))
            end do
            violation = candidate_violation(sc, dl, rmax, n, surface, scale)
            if (violation <= tol_candidate) then
                s = sc
                accepted = .true.
                return
            end if
            if (violation < best_violation) then
                best_violation = violation
                best = sc
            end if
        end do
    end subroutine try_candidates

    !> How far a candidate return is from valid, relative to the stress scale: negative
    !> multipliers, lost order, a violated Mohr-Coulomb plane (any ordering) or cut-off [-].
    pure real(wp) function candidate_violation(sc, dl, rmax, n, surface, scale)
        real(wp), intent(in) :: sc(3)
            !! returned principal stresses of the candidate [Pa]
        real(wp), intent(in) :: dl(3)
            !! its multipliers, in dl(1:n) [-]
        real(wp), intent(in) :: rmax(3)
            !! largest component of each return direction D b_i, in rmax(1:n) [Pa]
        integer, intent(in) :: n
            !! number of active planes
        type(mohr_coulomb_surface_type), intent(in) :: surface
            !! the planes of the step
        real(wp), intent(in) :: scale
            !! stress scale of the tolerances [Pa]

        real(wp) :: violation
        integer :: j

        violation = max(0.0_wp, sc(2) - sc(1), sc(3) - sc(2), &
            mohr_coulomb_yield(sc, surface%sin_friction, surface%k))
        do j = 1, n
            violation = max(violation, -dl(j)*rmax(j))
        end do
        if (surface%cutoff) violation = max(violation, maxval(sc) - surface%tension)
        candidate_violation = violation/scale
    end function candidate_violation

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

    include "mpm_spectral.inc"

end module mpm_material_mohr_coulomb
