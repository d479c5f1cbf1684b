!> Undrained clay: elastic-perfectly plastic (or softening) with the undrained shear strength
!> Su, in total stresses. Tresca in plane strain, von Mises in 3D.
!>
!> Yield: sqrt(J2) <= k, J2 = s:s/2 of the deviator s (no dependence on the mean stress: the
!> undrained strength of a saturated clay). `match` sets k from Su:
!>
!> - "plane_strain" (default): k = Su. At plastic flow in plane strain the out-of-plane
!>   deviator is zero (associated von Mises flow, no plastic eps_zz), so sqrt(J2) =
!>   (sigma_1 - sigma_3)/2: exactly Tresca's strength Su, as Prandtl's (2 + pi) Su assumes.
!> - "compression": k = 2 Su / sqrt(3), von Mises through Tresca's triaxial compression
!>   (q = sqrt(3 J2) = 2 Su), the usual match in 3D.
!>
!> Su grows with depth: Su(z) = Su + Su_gradient max(Su_elevation - z, 0), z the particle's
!> initial elevation (y in 2D, z in 3D), kept from its creation (state(2)); a state file
!> (load_state) keeps no such elevation, so a gradient with load_state is refused (the
!> constant Su needs no state). Softening to the
!> residual Su / St (St the sensitivity) with the accumulated plastic shear strain, linear or
!> exponential (`mpm_softening`).
!>
!> The return is radial and exact for the strength of the start of the step: with the trial
!> radius rho_tr = sqrt(J2_tr) > k, the deviator is scaled to k, the mean stress is the
!> elastic trial's (isochoric plastic flow), and the plastic multiplier dl = (rho_tr - k) / G
!> adds dl / sqrt(3) to the equivalent plastic shear strain, as for Drucker-Prager.
!>
!> State of a particle: state(1) = accumulated equivalent plastic shear strain [-], state(2) =
!> its initial elevation [m] (used with a gradient only).
!>
!> `materials[i].type = "tresca"`: keys `E`, `nu`, `rho` (`mpm_elastic_solid`), `Su`,
!> `Su_gradient`, `Su_elevation`, `match` and `softening` {`type`, `sensitivity`, `strain`}.
module mpm_material_tresca
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_softening, only: softening_weight, softening_none, softening_linear, &
        softening_exponential, softening_names
    use mpm_material, only: material_key_width, key_path_width, work_plastic
    use mpm_elastic_solid, only: elastic_solid_type, elastic_keys, add_elastic_trial
    use mpm_stress, only: mean_and_deviator
    implicit none
    private
    public :: tresca_material_type, new_tresca_material, match_plane_strain, match_compression

    real(wp), parameter :: sqrt3 = sqrt(3.0_wp)
    integer, parameter :: match_plane_strain = 1
        !! k = Su: Tresca's strength in plane strain
    integer, parameter :: match_compression = 2
        !! k = 2 Su / sqrt(3): Tresca's strength in triaxial compression
    character(len=*), parameter :: match_names(2) = [character(len=12) :: "plane_strain", &
        "compression"]
        !! names of `match`
    character(len=*), parameter :: tresca_softening_keys(*) = [character(len=11) :: "type", &
        "sensitivity", "strain"]
        !! keys of `materials[i].softening` of a Tresca material

    !> Undrained clay: Tresca / von Mises with Su growing with depth and softening.
    type, extends(elastic_solid_type) :: tresca_material_type
        real(wp) :: su = 0.0_wp
            !! undrained shear strength at Su_elevation and above [Pa]
        real(wp) :: su_gradient = 0.0_wp
            !! its increase per metre of depth below Su_elevation [Pa/m]
        real(wp) :: su_elevation = 0.0_wp
            !! elevation of Su [m] (only with a gradient)
        integer :: match = match_plane_strain
            !! how k follows from Su (`match_*`)
        integer :: softening = softening_none
            !! softening law (`mpm_softening`)
        real(wp) :: sensitivity = 1.0_wp
            !! St = peak Su / residual Su [-]
        real(wp) :: softening_strain = 0.0_wp
            !! plastic shear strain scale of the softening [-]
    contains
        procedure, nopass :: names => tresca_names
        procedure, nopass :: keys => tresca_keys
        procedure, nopass :: section_keys => tresca_section_keys
        procedure :: read => tresca_read
        procedure :: writes_plastic_strain => tresca_writes_plastic_strain
        procedure :: summary => tresca_summary
        procedure :: update_stress => tresca_update_stress
        procedure :: nstate => tresca_nstate
        procedure :: work_kind => tresca_work_kind
        procedure :: initial_state => tresca_initial_state
        procedure :: needs_initial_state => tresca_needs_initial_state
        procedure :: reduce_strength => tresca_reduce_strength
        !> The strength at a depth and after a plastic shear strain.
        procedure :: strength_at => tresca_strength_at
    end type tresca_material_type

contains

    !> Names accepted for `type`.
    pure subroutine tresca_names(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=material_key_width) :: "tresca"]
    end subroutine tresca_names

    !> Keys of a Tresca material.
    pure subroutine tresca_keys(list)
        character(len=material_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=material_key_width) :: elastic_keys, "Su", "Su_gradient", &
            "Su_elevation", "match", "softening"]
    end subroutine tresca_keys

    !> Key paths of `materials[i].softening`.
    pure subroutine tresca_section_keys(list)
        character(len=key_path_width), allocatable, intent(out) :: list(:)
            !! key paths

        integer :: k

        allocate (list(size(tresca_softening_keys)))
        do k = 1, size(tresca_softening_keys)
            list(k) = "softening."//trim(tresca_softening_keys(k))
        end do
    end subroutine tresca_section_keys

    !> Elasticity, then Su and its profile, the match and the softening.
    subroutine tresca_read(self, item, error)
        class(tresca_material_type), intent(inout) :: self
            !! the material
        type(cursor_type), intent(in) :: item
            !! the material object ("materials[i]")
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: softening
        logical :: found, has_gradient

        call self%read_elasticity(item, error)
        if (allocated(error)) return
        call item%get_real("Su", self%su, error, required=.true., at_least=0.0_wp, unit="Pa")
        if (allocated(error)) return
        call item%get_real("Su_gradient", self%su_gradient, error, at_least=0.0_wp, &
            unit="Pa/m", found=has_gradient)
        if (allocated(error)) return
        if (has_gradient) then
            call item%get_real("Su_elevation", self%su_elevation, error, required=.true., &
                unit="m")
            if (allocated(error)) return
        else if (item%has("Su_elevation")) then
            call item%fail(error, item%key_path("Su_elevation")//" only applies with " &
                //item%key_path("Su_gradient")//" (the elevation below which Su grows); " &
                //"remove it or give the gradient [Pa/m]")
            return
        end if
        if (self%su == 0.0_wp .and. self%su_gradient == 0.0_wp) then
            call item%fail(error, item%key_path("Su")//" = 0 with no Su_gradient leaves " &
                //"no strength: give Su > 0 [Pa], or Su_gradient > 0 [Pa/m] for a strength " &
                //"that grows from zero with depth")
            return
        end if
        call item%get_choice("match", match_names, [match_plane_strain, match_compression], &
            self%match, error)
        if (allocated(error)) return
        call item%get_section("softening", tresca_softening_keys, softening, error, found=found)
        if (allocated(error) .or. .not. found) return
        call softening%get_choice("type", softening_names, [softening_none, softening_linear, &
            softening_exponential], self%softening, error, required=.true.)
        if (allocated(error)) return
        if (self%softening == softening_none) then
            if (softening%has("sensitivity") .or. softening%has("strain")) call item%fail(error, &
                softening%path//".sensitivity and .strain only apply to softening.type = " &
                //'"linear" or "exponential" (here "none"); remove them')
            return
        end if
        call softening%get_real("sensitivity", self%sensitivity, error, required=.true., &
            at_least=1.0_wp)
        if (allocated(error)) return
        call softening%get_real("strain", self%softening_strain, error, required=.true., &
            above=0.0_wp)
    end subroutine tresca_read

    !> Construct a Tresca material (tests, tools).
    pure subroutine new_tresca_material(mat, young, poisson, density, su, su_gradient, &
            su_elevation, match, softening, sensitivity, softening_strain)
        type(tresca_material_type), intent(out) :: mat
            !! the material
        real(wp), intent(in) :: young, poisson, density
            !! E [Pa], nu [-], rho [kg/m3]
        real(wp), intent(in) :: su, su_gradient, su_elevation
            !! Su [Pa], its gradient with depth [Pa/m], the elevation of Su [m]
        integer, intent(in) :: match
            !! `match_plane_strain` or `match_compression`
        integer, intent(in) :: softening
            !! softening law (`mpm_softening`)
        real(wp), intent(in) :: sensitivity, softening_strain
            !! St [-] and the strain scale of the softening [-]

        call mat%set_elasticity(young, poisson, density)
        mat%su = su
        mat%su_gradient = su_gradient
        mat%su_elevation = su_elevation
        mat%match = match
        mat%softening = softening
        mat%sensitivity = sensitivity
        mat%softening_strain = softening_strain
    end subroutine new_tresca_material

    !> The plastic shear strain is the state this material writes.
    pure logical function tresca_writes_plastic_strain(self)
        class(tresca_material_type), intent(in) :: self
            !! the material
        tresca_writes_plastic_strain = .true.
    end function tresca_writes_plastic_strain

    !> The elastic line, then the strength.
    pure subroutine tresca_summary(self, text)
        class(tresca_material_type), intent(in) :: self
            !! the material
        character(len=:), allocatable, intent(out) :: text
            !! the lines

        call self%elasticity_summary(text)
        text = text//"    Su = "//fmt_real(self%su)//" Pa"
        if (self%su_gradient > 0.0_wp) text = text//" + "//fmt_real(self%su_gradient) &
            //" Pa/m below "//fmt_real(self%su_elevation)//" m"
        text = text//", k = "//trim(merge("Su           ", "2 Su / sqrt 3", &
            self%match == match_plane_strain))//" ("//trim(match_names(self%match))//")"
        if (self%softening /= softening_none) then
            text = text//new_line("a")//"    softening "//trim(softening_names(self%softening)) &
                //" to Su / "//fmt_real(self%sensitivity)//" over a plastic shear strain of " &
                //fmt_real(self%softening_strain)
        end if
        text = text//new_line("a")
    end subroutine tresca_summary

    !> Two state values: the plastic shear strain and the particle's peak Su.
    pure integer function tresca_nstate(self)
        class(tresca_material_type), intent(in) :: self
            !! the material
        tresca_nstate = 2
    end function tresca_nstate

    !> Plastic: the work beyond the stored elastic energy is dissipated.
    pure integer function tresca_work_kind(self)
        class(tresca_material_type), intent(in) :: self
            !! the material
        tresca_work_kind = work_plastic
    end function tresca_work_kind

    !> With a gradient, Su depends on each particle's initial elevation.
    pure logical function tresca_needs_initial_state(self)
        class(tresca_material_type), intent(in) :: self
            !! the material
        tresca_needs_initial_state = self%su_gradient > 0.0_wp
    end function tresca_needs_initial_state

    !> A new particle's initial elevation (the last axis), from which its Su follows.
    pure subroutine tresca_initial_state(self, x, state)
        class(tresca_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: x(:)
            !! the particle's initial position [m]
        real(wp), intent(inout) :: state(:)
            !! its state variables

        state(2) = x(size(x))
    end subroutine tresca_initial_state

    !> The peak Su of a particle of initial elevation z0.
    pure real(wp) function peak_su(self, z0)
        class(tresca_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: z0
            !! initial elevation [m]

        peak_su = self%su
        if (self%su_gradient > 0.0_wp) peak_su = self%su + self%su_gradient &
            *max(self%su_elevation - z0, 0.0_wp)
    end function peak_su

    !> Strength reduction: Su and its gradient divided by F.
    pure subroutine tresca_reduce_strength(self, factor, reduced)
        class(tresca_material_type), intent(inout) :: self
            !! the material
        real(wp), intent(in) :: factor
            !! strength reduction factor F > 0 [-]
        logical, intent(out) :: reduced
            !! whether it has a strength to reduce (it has)

        self%su = self%su/factor
        self%su_gradient = self%su_gradient/factor
        reduced = .true.
    end subroutine tresca_reduce_strength

    !> The radius k of the yield cylinder, sqrt(J2) <= k, for a peak Su after the plastic
    !> shear strain eps_q: Su softened towards Su / St, then matched.
    pure real(wp) function tresca_strength_at(self, su_peak, eps_q) result(k)
        class(tresca_material_type), intent(in) :: self
            !! the material
        real(wp), intent(in) :: su_peak
            !! the particle's peak Su [Pa]
        real(wp), intent(in) :: eps_q
            !! accumulated plastic shear strain [-]

        real(wp) :: w

        w = softening_weight(self%softening, self%softening_strain, eps_q)
        k = su_peak*(1.0_wp + w*(1.0_wp/self%sensitivity - 1.0_wp))
        if (self%match == match_compression) k = 2.0_wp*k/sqrt3
    end function tresca_strength_at

    !> Objective elastic trial stress, then the radial return to the cylinder.
    pure subroutine tresca_update_stress(self, stress, dstrain, omega, dt, state)
        class(tresca_material_type), intent(in) :: self
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
            !! state(1) plastic shear strain [-], state(2) initial elevation [m]

        real(wp) :: k, m, rho, dev(6)
        integer :: n

        n = size(stress)
        k = self%strength_at(peak_su(self, state(2)), state(1))
        call add_elastic_trial(self, stress, dstrain, omega)
        call mean_and_deviator(stress, m, dev(1:n), rho)
        if (rho <= k) return
        stress = dev(1:n)*(k/rho)
        stress(1:3) = stress(1:3) + m
        ! de_p = dl s / (2 rho), dl = (rho - k) / G: d eps_q = dl / sqrt(3)
        state(1) = state(1) + (rho - k)/(self%shear*sqrt3)
    end subroutine tresca_update_stress

end module mpm_material_tresca
