!> Drucker-Prager elasto-plasticity matched to Mohr-Coulomb, with a tension cut-off,
!> non-associated flow and softening of the strength with the plastic shear strain.
!>
!> Stress is tension positive (`mpm_stress`). With the mean stress m = tr(sigma)/3 (tension
!> positive), the deviator s = sigma - m I and J2 = s:s/2, the yield surfaces are
!>
!> - cone:    f1 = sqrt(J2) + alpha m - k <= 0 (compression, m < 0, raises the shear strength)
!> - tension: f2 = m - sigma_t <= 0, sigma_t = min(tension_cutoff, k/alpha) (the apex k/alpha
!>   when no cut-off is given; no cut-off at all when alpha = 0 and none is given)
!>
!> and the plastic potentials g1 = sqrt(J2) + alpha_psi m (dilatancy angle psi) and g2 = m.
!> The constants alpha, k, alpha_psi follow from the Mohr-Coulomb phi, c, psi through the
!> selected cone (see `drucker_prager_cone`).
!>
!> The return mapping is exact (closed form): with linear elasticity and the strength of the
!> start of the step, the trial stress returns radially in the deviatoric plane to the cone, to
!> the tension plane, or to the corner of both (the apex when sigma_t = k/alpha).
!>
!> State of a particle: state(1) = accumulated equivalent plastic shear strain
!> eps_q = sum sqrt(2/3 de_p : de_p) (de_p the deviatoric plastic strain increment) [-],
!> state(2) = accumulated plastic volumetric strain, tension positive (dilation > 0) [-];
!> with `separation` (see `mpm_separation`), state(3) = opening strain [-].
!>
!> `materials[i].type = "drucker_prager"`: keys `E`, `nu`, `rho` (`mpm_elastic_solid`), the
!> strength (`mpm_strength`) and `cone`.
module mpm_material_drucker_prager
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    use mpm_softening, only: softened_strength, softening_none
    use mpm_separation, only: close_opening
    use mpm_material, only: material_key_width, work_plastic, update_each, material_chunk, chunk_in
    use mpm_elastic_solid, only: elastic_solid_type, elastic_keys, add_elastic_trial
    use mpm_strength, only: strength_type, read_strength, strength_keys, strength_section_keys, &
        strength_summary, reduced_strength
    use mpm_stress, only: mean_and_deviator
    implicit none
    private
    public :: drucker_prager_material_type, new_drucker_prager_material, drucker_prager_cone
    public :: cone_plane_strain, cone_compression, cone_extension, cone_names

    real(wp), parameter :: sqrt3 = sqrt(3.0_wp)

    ! Drucker-Prager cone matched to Mohr-Coulomb
    integer, parameter :: cone_plane_strain = 1  !! same collapse load in plane strain
    integer, parameter :: cone_compression = 2   !! outer cone: through the compression corners
    integer, parameter :: cone_extension = 3     !! inner cone: through the extension corners
    character(len=*), parameter :: cone_names(3) = [character(len=12) :: "plane_strain", &
        "compression", "extension"]
        !! names of the cones in the case file (`materials[i].cone`)

    !> Drucker-Prager cone with tension cut-off, matched to Mohr-Coulomb parameters; E, nu,
    !> rho, G and lambda come from `elastic_solid_type` (lambda = K - 2G/3 here).
    type, extends(elastic_solid_type) :: drucker_prager_material_type
        real(wp) :: bulk = 0.0_wp
            !! bulk modulus K [Pa]
        type(strength_type) :: strength
            !! friction, cohesion, dilatancy, tension cut-off (largest mean stress allowed;
            !! negative: the apex of the cone), softening and separation
        integer :: cone = cone_plane_strain
            !! cone matched to Mohr-Coulomb (`cone_*`)
    contains
        procedure, nopass :: names => drucker_prager_names
        procedure, nopass :: keys => drucker_prager_keys
        procedure, nopass :: section_keys => strength_section_keys
        procedure :: read => drucker_prager_read
        procedure :: writes_plastic_strain => drucker_prager_writes_plastic_strain
        procedure :: summary => drucker_prager_summary
        procedure :: update_stress => drucker_prager_update_stress
            !! exact return mapping of one particle over one step
        procedure :: update_stress_block => drucker_prager_update_stress_block
            !! the same for a block, without a branch per particle (vectorised)
        procedure :: nstate => drucker_prager_nstate
            !! two state values: eps_q and the plastic volumetric strain
        procedure :: strength_after => drucker_prager_strength
            !! phi, c and psi after a given plastic shear strain
        procedure :: work_kind => drucker_prager_work_kind
            !! plastic: the work beyond the stored elastic energy is dissipated
        !> K0 after Jaky (1944): 1 - sin(phi), of the peak friction angle.
        procedure :: at_rest_ratio => drucker_prager_at_rest_ratio
        procedure :: reduce_strength => drucker_prager_reduce_strength
            !! tan(phi), c and the tensile strength divided by F (`reduced_strength`)
    end type drucker_prager_material_type

contains

    !> Names accepted for `type`.
    pure subroutine drucker_prager_names(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=material_key_width) :: "drucker_prager"]
    end subroutine drucker_prager_names

    !> Keys of a Drucker-Prager material.
    pure subroutine drucker_prager_keys(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=material_key_width) :: elastic_keys, strength_keys, "cone"]
    end subroutine drucker_prager_keys

    !> Elasticity (`E`, `nu`, `rho`), strength (mpm_strength), then `cone`.
    subroutine drucker_prager_read(self, item, error)
        class(drucker_prager_material_type), intent(inout) :: self
            !! the material
        type(cursor_type), intent(in) :: item
            !! the material object ("materials[i]")
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(strength_type) :: strength
        integer :: cone

        call self%read_elasticity(item, error)
        if (allocated(error)) return
        call read_strength(item, "Drucker-Prager", strength, error)
        if (allocated(error)) return
        cone = self%cone
        call item%get_choice("cone", cone_names, [cone_plane_strain, cone_compression, &
            cone_extension], cone, error)
        if (allocated(error)) return
        call set_up(self, strength, cone)
    end subroutine drucker_prager_read

    !> The plastic shear strain is the state this material writes.
    pure logical function drucker_prager_writes_plastic_strain(self)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material

        drucker_prager_writes_plastic_strain = .true.
    end function drucker_prager_writes_plastic_strain

    !> The elastic line, then the strength with the cone.
    pure subroutine drucker_prager_summary(self, text)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material
        character(len=:), allocatable, intent(out) :: text
            !! the lines

        call self%elasticity_summary(text)
        text = text//strength_summary(self%strength, ", cone "//trim(cone_names(self%cone)))
    end subroutine drucker_prager_summary

    !> K0 of a normally consolidated soil after Jaky (1944): 1 - sin(phi), phi the peak
    !> friction angle.
    pure real(wp) function drucker_prager_at_rest_ratio(self)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material

        drucker_prager_at_rest_ratio = 1.0_wp - sin(self%strength%friction)
    end function drucker_prager_at_rest_ratio

    !> Strength reduction: the strength divided by F (`mpm_strength::reduced_strength`).
    pure subroutine drucker_prager_reduce_strength(self, factor, reduced)
        class(drucker_prager_material_type), intent(inout) :: self
            !! the material
        real(wp), intent(in) :: factor
            !! strength reduction factor F > 0 [-]
        logical, intent(out) :: reduced
            !! whether it has a strength to reduce (it has)

        call set_up(self, reduced_strength(self%strength, factor), self%cone)
        reduced = .true.
    end subroutine drucker_prager_reduce_strength

    !> Where the work of the stresses goes: plastic dissipation beyond the stored part.
    pure integer function drucker_prager_work_kind(self)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material
        drucker_prager_work_kind = work_plastic
    end function drucker_prager_work_kind

    !> Construct a Drucker-Prager material from E, nu, rho, its strength and its cone.
    pure subroutine new_drucker_prager_material(mat, young, poisson, density, strength, cone)
        type(drucker_prager_material_type), intent(out) :: mat
            !! the material
        real(wp), intent(in) :: young
            !! Young's modulus [Pa]
        real(wp), intent(in) :: poisson
            !! Poisson's ratio [-]
        real(wp), intent(in) :: density
            !! mass density [kg/m3]
        type(strength_type), intent(in) :: strength
            !! friction, cohesion, dilatancy, cut-off, softening, separation
        integer, intent(in) :: cone
            !! `cone_plane_strain`, `cone_compression` or `cone_extension`

        call mat%set_elasticity(young, poisson, density)
        call set_up(mat, strength, cone)
    end subroutine new_drucker_prager_material

    !> Strength and cone of a material whose elasticity is set; K and lambda = K - 2G/3.
    pure subroutine set_up(mat, strength, cone)
        class(drucker_prager_material_type), intent(inout) :: mat
            !! the material
        type(strength_type), intent(in) :: strength
            !! its strength
        integer, intent(in) :: cone
            !! its cone

        mat%bulk = mat%young/(3.0_wp*(1.0_wp - 2.0_wp*mat%poisson))
        mat%lame = mat%bulk - 2.0_wp*mat%shear/3.0_wp
        mat%strength = strength
        mat%cone = cone
    end subroutine set_up

    !> Two state values per particle, eps_q and the plastic volumetric strain, and with
    !> separation a third, the opening strain.
    pure integer function drucker_prager_nstate(self)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material
        drucker_prager_nstate = merge(3, 2, self%strength%separation)
    end function drucker_prager_nstate

    !> Friction, cohesion and dilatancy after the plastic shear strain eps_q.
    !>
    !> Linear: x = x_p + (x_r - x_p) min(eps_q / eps_s, 1); exponential:
    !> x = x_r + (x_p - x_r) exp(-eps_q / eps_s); none: the peak values.
    pure subroutine drucker_prager_strength(self, eps_q, friction, cohesion, dilatancy)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: eps_q
            !! accumulated equivalent plastic shear strain [-]
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
        end associate
    end subroutine drucker_prager_strength

    !> Drucker-Prager constants of f = sqrt(J2) + alpha m - k (m tension positive) and of the
    !> potential g = sqrt(J2) + alpha_psi m, matched to Mohr-Coulomb phi, c, psi.
    !>
    !> - compression (outer cone, through the triaxial compression corners):
    !>   alpha = 2 sqrt(3) sin(phi) / (3 - sin(phi)), k = 2 sqrt(3) c cos(phi) / (3 - sin(phi)),
    !>   alpha_psi = 2 sqrt(3) sin(psi) / (3 - sin(psi)); triaxial compression strength
    !>   q = sqrt(3 J2) = 6 (c cos(phi) + p sin(phi)) / (3 - sin(phi)), p = -m, as Mohr-Coulomb.
    !> - extension (inner cone, through the triaxial extension corners): 3 + sin instead of
    !>   3 - sin; strength q = 6 (c cos(phi) + p sin(phi)) / (3 + sin(phi)).
    !> - plane strain: alpha_psi = sqrt(3) sin(psi) / sqrt(3 + sin(psi)^2),
    !>   alpha = sqrt(3) sin(phi) sqrt(3 + sin(psi)^2) / (3 + sin(phi) sin(psi)),
    !>   k = sqrt(3) c cos(phi) sqrt(3 + sin(psi)^2) / (3 + sin(phi) sin(psi)).
    !>   Why: at steady plastic flow in plane strain the plastic eps_zz rate is zero, so
    !>   s_zz = -2 alpha_psi sqrt(J2)/3, hence sqrt(J2) = t / sqrt(1 - alpha_psi^2/3) and
    !>   m = s_c - alpha_psi sqrt(J2)/3, with t = (sigma_1 - sigma_3)/2 and s_c =
    !>   (sigma_1 + sigma_3)/2 the in-plane Mohr circle (tension positive). f = 0 becomes
    !>   t (1 - alpha alpha_psi/3) / sqrt(1 - alpha_psi^2/3) = k - alpha s_c, which is
    !>   Mohr-Coulomb's t = c cos(phi) - s_c sin(phi) for the constants above; alpha_psi gives
    !>   Mohr-Coulomb's plane-strain dilatancy d eps_v^p = sin(psi) (d eps_1^p - d eps_3^p).
    !>   For psi = phi (associated) these are the constants usually quoted, tan(beta) =
    !>   3 tan(phi) / sqrt(9 + 12 tan(phi)^2), k = 3 c / sqrt(9 + 12 tan(phi)^2); for psi = 0
    !>   they are alpha = sin(phi), k = c cos(phi) (the associated constants with psi = 0
    !>   would give a plane-strain strength below Mohr-Coulomb's).
    pure subroutine drucker_prager_cone(cone, friction, cohesion, dilatancy, alpha, k, alpha_psi)
        integer, intent(in) :: cone
            !! `cone_plane_strain`, `cone_compression` or `cone_extension`
        real(wp), intent(in) :: friction
            !! friction angle phi [rad]
        real(wp), intent(in) :: cohesion
            !! cohesion c [Pa]
        real(wp), intent(in) :: dilatancy
            !! dilatancy angle psi [rad]
        real(wp), intent(out) :: alpha
            !! friction coefficient of the cone [-]
        real(wp), intent(out) :: k
            !! shear strength sqrt(J2) at zero mean stress [Pa]
        real(wp), intent(out) :: alpha_psi
            !! dilatancy coefficient of the plastic potential [-]

        real(wp) :: sphi, cphi, spsi, r

        sphi = sin(friction)
        cphi = cos(friction)
        spsi = sin(dilatancy)
        select case (cone)
        case (cone_compression)
            alpha = 2.0_wp*sqrt3*sphi/(3.0_wp - sphi)
            k = 2.0_wp*sqrt3*cohesion*cphi/(3.0_wp - sphi)
            alpha_psi = 2.0_wp*sqrt3*spsi/(3.0_wp - spsi)
        case (cone_extension)
            alpha = 2.0_wp*sqrt3*sphi/(3.0_wp + sphi)
            k = 2.0_wp*sqrt3*cohesion*cphi/(3.0_wp + sphi)
            alpha_psi = 2.0_wp*sqrt3*spsi/(3.0_wp + spsi)
        case default
            r = sqrt(3.0_wp + spsi*spsi)
            alpha = sqrt3*sphi*r/(3.0_wp + sphi*spsi)
            k = sqrt3*cohesion*cphi*r/(3.0_wp + sphi*spsi)
            alpha_psi = sqrt3*spsi/r
        end select
    end subroutine drucker_prager_cone

    !> Objective elastic trial stress, then the exact return to the cone, the tension plane or
    !> their corner (the apex when the cut-off is the apex).
    !>
    !> With the trial mean stress m_tr and radius rho_tr = sqrt(J2_tr), plastic multipliers
    !> dl1 (cone) and dl2 (tension) give m = m_tr - K (alpha_psi dl1 + dl2), rho = rho_tr - G dl1,
    !> the deviator keeping its direction:
    !> - cone:    dl1 = f1_tr / (G + K alpha alpha_psi), dl2 = 0, valid when m <= sigma_t;
    !> - tension: dl1 = 0, m = sigma_t, valid when rho_tr <= rho_c = k - alpha sigma_t;
    !> - corner:  rho = rho_c, m = sigma_t, dl1 = (rho_tr - rho_c) / G,
    !>   dl2 = (m_tr - sigma_t) / K - alpha_psi dl1 (>= 0 exactly when the cone return fails).
    pure subroutine drucker_prager_update_stress(self, stress, dstrain, omega, dt, state)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material
        real(wp), intent(inout) :: stress(:)
            !! Cauchy stress, 4 (2D) or 6 (3D) components, tension positive [Pa]
        real(wp), intent(in) :: dstrain(:)
            !! strain increment, tensor components [-]
        real(wp), intent(in) :: omega(3)
            !! spin increment W dt (xy, yz, zx) [-]
        real(wp), intent(in) :: dt
            !! time step [s] (unused: rate independent)
        real(wp), intent(inout) :: state(:)
            !! state(1) eps_q [-], state(2) plastic volumetric strain [-], with separation
            !! state(3) opening strain [-]

        real(wp) :: friction, cohesion, dilatancy, alpha, k, alpha_psi
        real(wp) :: sigma_t, rho_c, m_tr, rho_tr, f_tr, m, rho, dl1, dl2
        real(wp) :: dev(6), de(6)
        integer :: n
        logical :: cutoff, open

        call self%strength_after(state(1), friction, cohesion, dilatancy)
        call drucker_prager_cone(self%cone, friction, cohesion, dilatancy, alpha, k, alpha_psi)

        n = size(dstrain)
        de(1:n) = dstrain
        if (self%strength%separation) then
            call close_opening(de(1:n), state(3), state(1), open)
            if (open) then
                stress = 0.0_wp
                return
            end if
        end if
        ! elastic trial stress from the rotated stress of the start of the step
        call add_elastic_trial(self, stress, de(1:n), omega)

        call mean_stress_limit(self, alpha, k, cutoff, sigma_t)

        call mean_and_deviator(stress, m_tr, dev(1:n), rho_tr)
        f_tr = rho_tr + alpha*m_tr - k
        if (f_tr <= 0.0_wp .and. (.not. cutoff .or. m_tr <= sigma_t)) return

        dl1 = 0.0_wp
        dl2 = 0.0_wp
        m = m_tr
        if (f_tr > 0.0_wp) then
            dl1 = f_tr/(self%shear + self%bulk*alpha*alpha_psi)
            m = m_tr - self%bulk*alpha_psi*dl1
        end if
        if (f_tr > 0.0_wp .and. (.not. cutoff .or. m <= sigma_t)) then
            ! cone: rho >= rho_c >= 0 in exact arithmetic; the max guards round-off
            rho = max(rho_tr - self%shear*dl1, 0.0_wp)
        else
            ! here m_tr > sigma_t: the tension plane or the corner with the cone
            rho_c = max(k - alpha*sigma_t, 0.0_wp)
            m = sigma_t
            if (rho_tr <= rho_c) then
                dl1 = 0.0_wp
                rho = rho_tr
                dl2 = (m_tr - sigma_t)/self%bulk
            else
                dl1 = (rho_tr - rho_c)/self%shear
                rho = rho_c
                dl2 = max((m_tr - sigma_t)/self%bulk - alpha_psi*dl1, 0.0_wp)
            end if
        end if

        ! radial return in the deviatoric plane
        if (rho_tr > 0.0_wp) then
            stress = dev(1:n)*(rho/rho_tr)
        else
            stress = 0.0_wp
        end if
        stress(1:3) = stress(1:3) + m

        ! de_p = dl1 s/(2 rho): |de_p| = dl1/sqrt(2), so d eps_q = sqrt(2/3) |de_p| = dl1/sqrt(3)
        state(1) = state(1) + dl1/sqrt3
        state(2) = state(2) + alpha_psi*dl1 + dl2
        ! separation: a return to the stress-free apex opens the material by its dilation
        if (self%strength%separation .and. rho <= 0.0_wp .and. m == 0.0_wp) then
            state(3) = state(3) + alpha_psi*dl1 + dl2
            stress = 0.0_wp
        end if
    end subroutine drucker_prager_update_stress

    !> The tension limit on the mean stress: the apex k / alpha, or the cut-off below it; none
    !> for a cylinder (alpha = 0) without a given cut-off.
    pure subroutine mean_stress_limit(self, alpha, k, cutoff, sigma_t)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: alpha, k
            !! the cone's constants (drucker_prager_cone)
        logical, intent(out) :: cutoff
            !! whether the mean stress is limited
        real(wp), intent(out) :: sigma_t
            !! its limit (0 without one) [Pa]

        cutoff = alpha > 0.0_wp .or. self%strength%tension_cutoff >= 0.0_wp
        sigma_t = 0.0_wp
        if (alpha > 0.0_wp) then
            sigma_t = k/alpha
            if (self%strength%tension_cutoff >= 0.0_wp) sigma_t = min(sigma_t, self%strength%tension_cutoff)
        else if (cutoff) then
            sigma_t = self%strength%tension_cutoff
        end if
    end subroutine mean_stress_limit

    !> drucker_prager_update_stress of a block of particles, in chunks copied to structures of
    !> arrays: the elastic predictor and the return (cone, tension plane, corner or none) as
    !> one loop without a branch per particle, every region computed and the valid one chosen
    !> (merge), so that it vectorises; the same operations as drucker_prager_update_stress,
    !> the cone's constants once per block. Softening (constants per particle) and separation
    !> take drucker_prager_update_stress particle by particle.
    pure subroutine drucker_prager_update_stress_block(self, n, stress, dstrain, omega, dt, state)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the block
        real(wp), intent(inout) :: stress(:, :)
            !! Cauchy stresses (4 or 6, at least n), tension positive [Pa]
        real(wp), intent(in) :: dstrain(:, :)
            !! strain increments D dt (tensor components, as stress) [-]
        real(wp), intent(in) :: omega(:, :)
            !! spin increments W dt (xy, yz, zx; 3, at least n) [-]
        real(wp), intent(in) :: dt
            !! time step [s] (unused: rate independent)
        real(wp), intent(inout) :: state(:, :)
            !! states (see drucker_prager_update_stress; at least n)

        real(wp) :: t(material_chunk, 6), d(material_chunk, 6), w(material_chunk, 3)
        real(wp) :: dq(material_chunk), dv(material_chunk)
        real(wp) :: friction, cohesion, dilatancy, alpha, k, alpha_psi, sigma_t
        integer :: j, j0, nc, ns
        logical :: cutoff

        if (self%strength%softening /= softening_none .or. self%strength%separation) then
            call update_each(self, n, stress, dstrain, omega, dt, state)
            return
        end if
        call self%strength_after(0.0_wp, friction, cohesion, dilatancy)
        call drucker_prager_cone(self%cone, friction, cohesion, dilatancy, alpha, k, alpha_psi)
        call mean_stress_limit(self, alpha, k, cutoff, sigma_t)

        ns = size(stress, 1)
        t = 0.0_wp
        d = 0.0_wp
        do j0 = 1, n, material_chunk
            nc = min(material_chunk, n - j0 + 1)
            call chunk_in(stress, dstrain, omega, j0, nc, t, d, w)
            call return_chunk(self, nc, ns, t, d, w, alpha, k, alpha_psi, cutoff, sigma_t, dq, dv)
            do j = 1, nc
                stress(1:ns, j0 + j - 1) = t(j, 1:ns)
                state(1, j0 + j - 1) = state(1, j0 + j - 1) + dq(j)
                state(2, j0 + j - 1) = state(2, j0 + j - 1) + dv(j)
            end do
        end do
    end subroutine drucker_prager_update_stress_block

    !> The predictor and the return of a chunk (see drucker_prager_update_stress), one loop
    !> over the particles without branches: the regions' multipliers are computed for every
    !> particle with safe operands and the valid one is chosen.
    pure subroutine return_chunk(self, n, ns, stress, dstrain, omega, alpha, k, alpha_psi, &
            cutoff, sigma_t, dq, dv)
        class(drucker_prager_material_type), intent(in) :: self
            !! the material
        integer, intent(in) :: n
            !! particles in the chunk
        integer, intent(in) :: ns
            !! stress components (4 or 6; the others are zero)
        real(wp), intent(inout) :: stress(material_chunk, 6)
            !! stresses (particle, component); on exit the updated ones [Pa]
        real(wp), intent(in) :: dstrain(material_chunk, 6)
            !! strain increments [-]
        real(wp), intent(in) :: omega(material_chunk, 3)
            !! spin increments [-]
        real(wp), intent(in) :: alpha, k, alpha_psi
            !! the cone's constants (drucker_prager_cone)
        logical, intent(in) :: cutoff
            !! whether the mean stress is limited
        real(wp), intent(in) :: sigma_t
            !! its limit [Pa]
        real(wp), intent(out) :: dq(material_chunk)
            !! increments of eps_q [-]
        real(wp), intent(out) :: dv(material_chunk)
            !! increments of the plastic volumetric strain [-]

        real(wp) :: g, g2, lame, bulk, limit, rho_c, stiffness
        real(wp) :: a1, a2, a3, a4, a5, a6, o1, o2, o3, dvol, t1, t2, t3, t4, t5, t6
        real(wp) :: m_tr, d1, d2, d3, rho_tr, f_tr, dl1c, mc, dl1t, dl2t, rho_t, dl1, dl2, m
        real(wp) :: rho, ratio, full, corner, opening, rho_cone, dl2_corner
        real(wp) :: r1, r2, r3, r4, r5, r6
        logical :: elastic, cone, plane
        integer :: j

        g = self%shear
        g2 = 2.0_wp*g
        lame = self%lame
        bulk = self%bulk
        ! without a limit no mean stress exceeds it (huge stays finite in the comparisons)
        limit = merge(sigma_t, huge(1.0_wp), cutoff)
        rho_c = max(k - alpha*sigma_t, 0.0_wp)
        full = merge(1.0_wp, 0.0_wp, ns == 6)
        stiffness = g + bulk*alpha*alpha_psi
        do j = 1, n
            a1 = stress(j, 1)
            a2 = stress(j, 2)
            a3 = stress(j, 3)
            a4 = stress(j, 4)
            a5 = stress(j, 5)
            a6 = stress(j, 6)
            o1 = omega(j, 1)
            o2 = omega(j, 2)
            o3 = omega(j, 3)
            ! the Jaumann rotation of mpm_stress (in 2D o2, o3, a5, a6 are zero), then Hooke
            t1 = a1 + 2.0_wp*(o1*a4 - o3*a6)
            t2 = a2 + 2.0_wp*(o2*a5 - o1*a4)
            t3 = a3 + 2.0_wp*(o3*a6 - o2*a5)
            t4 = a4 + (o1*(a2 - a1) + o2*a6 - o3*a5)
            t5 = a5 + (o2*(a3 - a2) + o3*a4 - o1*a6)
            t6 = a6 + (o3*(a1 - a3) + o1*a5 - o2*a4)
            dvol = dstrain(j, 1) + dstrain(j, 2) + dstrain(j, 3)
            t1 = t1 + g2*dstrain(j, 1) + lame*dvol
            t2 = t2 + g2*dstrain(j, 2) + lame*dvol
            t3 = t3 + g2*dstrain(j, 3) + lame*dvol
            t4 = t4 + g2*dstrain(j, 4)
            t5 = (t5 + g2*dstrain(j, 5))*full
            t6 = (t6 + g2*dstrain(j, 6))*full
            ! mean_and_deviator
            m_tr = (t1 + t2 + t3)/3.0_wp
            d1 = t1 - m_tr
            d2 = t2 - m_tr
            d3 = t3 - m_tr
            rho_tr = sqrt(0.5_wp*(d1*d1 + d2*d2 + d3*d3 + 2.0_wp*(t4*t4 + t5*t5 + t6*t6)))
            f_tr = rho_tr + alpha*m_tr - k
            ! Every region is computed and the valid one chosen. The compiler moves the work
            ! only one choice needs into a branch of its own and turns it back into a
            ! selection only when floating-point operations may be run speculatively:
            ! CMakeLists.txt builds this file with -fno-trapping-math (no value changes),
            ! without which the loop does not vectorise.
            elastic = f_tr <= 0.0_wp .and. m_tr <= limit
            ! the cone
            dl1c = max(f_tr, 0.0_wp)/stiffness
            mc = m_tr - bulk*alpha_psi*dl1c
            rho_cone = max(rho_tr - g*dl1c, 0.0_wp)
            cone = f_tr > 0.0_wp .and. mc <= limit
            ! the tension plane (rho_tr <= rho_c) or the corner with the cone
            plane = rho_tr <= rho_c
            corner = (rho_tr - rho_c)/g
            dl1t = merge(0.0_wp, corner, plane)
            rho_t = merge(rho_tr, rho_c, plane)
            opening = (m_tr - sigma_t)/bulk
            dl2_corner = max(opening - alpha_psi*dl1t, 0.0_wp)
            dl2t = merge(opening, dl2_corner, plane)
            dl1 = merge(dl1c, dl1t, cone)
            dl2 = merge(0.0_wp, dl2t, cone)
            m = merge(mc, sigma_t, cone)
            rho = merge(rho_cone, rho_t, cone)
            ! radial return in the deviatoric plane (a zero deviator stays zero)
            ratio = merge(rho/merge(rho_tr, 1.0_wp, rho_tr > 0.0_wp), 0.0_wp, rho_tr > 0.0_wp)
            r1 = d1*ratio + m
            r2 = d2*ratio + m
            r3 = d3*ratio + m
            r4 = t4*ratio
            r5 = t5*ratio
            r6 = t6*ratio
            stress(j, 1) = merge(t1, r1, elastic)
            stress(j, 2) = merge(t2, r2, elastic)
            stress(j, 3) = merge(t3, r3, elastic)
            stress(j, 4) = merge(t4, r4, elastic)
            stress(j, 5) = merge(t5, r5, elastic)
            stress(j, 6) = merge(t6, r6, elastic)
            dq(j) = merge(0.0_wp, dl1/sqrt3, elastic)
            dv(j) = merge(0.0_wp, alpha_psi*dl1 + dl2, elastic)
        end do
    end subroutine return_chunk

end module mpm_material_drucker_prager
