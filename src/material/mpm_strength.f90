!> The strength Mohr-Coulomb and Drucker-Prager materials share: friction, cohesion,
!> dilatancy, tension cutoff, separation and softening (`strength_type`), its keys, how they
!> are read and checked, and its lines of the --check summary.
module mpm_strength
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real, fmt_below
    use mpm_case_cursor, only: cursor_type
    use mpm_material, only: material_key_width, key_path_width
    use mpm_softening, only: softening_none, softening_linear, softening_exponential, &
        softening_names
    implicit none
    private
    public :: strength_type, read_strength, strength_keys, softening_keys, strength_section_keys
    public :: strength_summary, degree, reduced_strength

    character(len=*), parameter :: strength_keys(*) = [character(len=material_key_width) :: &
        "phi", "c", "psi", "tension_cutoff", "softening", "separation"]
        !! keys of the strength of a material
    character(len=*), parameter :: softening_keys(*) = [character(len=12) :: "type", &
        "phi_residual", "c_residual", "psi_residual", "strain"]
        !! keys of `materials[i].softening`
    real(wp), parameter :: degree = acos(-1.0_wp)/180.0_wp
        !! one degree [rad]: angles are given in degrees and stored in radians

    !> Strength of a frictional material: peak and residual values and the softening law.
    type :: strength_type
        real(wp) :: friction = 0.0_wp
            !! peak friction angle phi [rad] (input in degrees)
        real(wp) :: cohesion = 0.0_wp
            !! peak cohesion c [Pa]
        real(wp) :: dilatancy = 0.0_wp
            !! peak dilatancy angle psi [rad] (input in degrees), 0 <= psi <= phi
        real(wp) :: tension_cutoff = -1.0_wp
            !! tensile strength: largest mean (DP) or principal (MC) stress allowed [Pa];
            !! negative when not given (then the apex of the cone, c / tan(phi), limits it)
        logical :: separation = .false.
            !! cohesionless separation: dilation at the stress-free apex opens the material,
            !! and compression closes it again before any stress builds (c = 0 or
            !! tension_cutoff = 0; state(3) = opening strain, see `mpm_separation`)
        integer :: softening = softening_none
            !! softening law of phi, c and psi with the plastic shear strain (`mpm_softening`)
        real(wp) :: friction_residual = 0.0_wp
            !! residual friction angle [rad] (softening only)
        real(wp) :: cohesion_residual = 0.0_wp
            !! residual cohesion [Pa] (softening only)
        real(wp) :: dilatancy_residual = 0.0_wp
            !! residual dilatancy angle [rad] (softening only)
        real(wp) :: softening_strain = 0.0_wp
            !! for the linear law, the plastic shear strain at which the residual values are
            !! reached; for the exponential law, the strain scale eta_0 in
            !! x = x_r + (x_p - x_r) exp(-eps_p / eta_0) [-]
    end type strength_type

contains

    !> Key paths of `materials[i].softening`, "softening.key".
    pure subroutine strength_section_keys(list)
        character(len=key_path_width), allocatable, intent(out) :: list(:)
            !! key paths

        integer :: k

        allocate (list(size(softening_keys)))
        do k = 1, size(softening_keys)
            list(k) = "softening."//trim(softening_keys(k))
        end do
    end subroutine strength_section_keys

    !> Summary lines of a strength: "phi = ..., c = ..., psi = ..., tension cutoff ...", with
    !> `extra` before the separation flag, then the softening.
    pure function strength_summary(strength, extra) result(text)
        type(strength_type), intent(in) :: strength
            !! the strength
        character(len=*), intent(in) :: extra
            !! text of the material on the first line (", cone compression"), or ""
        character(len=:), allocatable :: text
            !! the lines, each ending in new_line("a")

        character(len=*), parameter :: nl = new_line("a")
        character(len=:), allocatable :: line

        associate (mat => strength)
            line = "    phi = "//fmt_deg(mat%friction)//" deg, c = "//fmt_real(mat%cohesion) &
                //" Pa, psi = "//fmt_deg(mat%dilatancy)//" deg, tension cutoff "
            if (mat%tension_cutoff >= 0.0_wp) then
                line = line//fmt_real(mat%tension_cutoff)//" Pa"
            else
                line = line//"at the apex"
            end if
            line = line//extra
            if (mat%separation) line = line//", separation"
            text = line//nl
            if (mat%softening == softening_none) then
                text = text//"    no softening"//nl
            else
                text = text//"    softening "//trim(softening_names(mat%softening))//" to phi = " &
                    //fmt_deg(mat%friction_residual)//" deg, c = "//fmt_real(mat%cohesion_residual) &
                    //" Pa, psi = "//fmt_deg(mat%dilatancy_residual)//" deg"
                if (mat%softening == softening_linear) then
                    text = text//" at plastic shear strain "//fmt_real(mat%softening_strain)//nl
                else
                    text = text//", plastic shear strain scale "//fmt_real(mat%softening_strain)//nl
                end if
            end if
        end associate
    end function strength_summary

    !> An angle in degrees, at 12 digits to hide the round-off of the degree-radian
    !> conversion, so 30 degrees shows as "30".
    pure function fmt_deg(angle) result(text)
        real(wp), intent(in) :: angle
            !! angle [rad]
        character(len=:), allocatable :: text

        text = fmt_real(angle/degree, 12)
    end function fmt_deg

    !> Strength of a Mohr-Coulomb or Drucker-Prager material: `phi`, `c`, `psi`,
    !> `tension_cutoff`, `separation` and `softening`. Angles are read in degrees and stored in
    !> radians.
    subroutine read_strength(item, family, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        character(len=*), intent(in) :: family
            !! "Mohr-Coulomb" or "Drucker-Prager", for messages
        type(strength_type), intent(inout) :: mat
            !! strength being resolved
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        character(len=:), allocatable :: limit
        logical :: found
        real(wp) :: phi, c, psi, cutoff, apex

        phi = 0.0_wp
        c = 0.0_wp
        psi = 0.0_wp
        cutoff = -1.0_wp
        call item%get_real("phi", phi, error, required=.true., at_least=0.0_wp, &
            below=90.0_wp, unit="deg")
        if (allocated(error)) return
        call item%get_real("c", c, error, at_least=0.0_wp, unit="Pa")
        if (allocated(error)) return
        if (phi == 0.0_wp .and. c == 0.0_wp) then
            call item%fail(error, item%path//".phi = 0 and "//item%path//".c = 0: a "//family &
                //" material with phi = 0 and c = 0 has no strength; use a newtonian fluid, " &
                //"or give phi > 0 [deg] or c > 0 [Pa]")
            return
        end if
        call item%get_real("psi", psi, error, at_least=0.0_wp, unit="deg")
        if (allocated(error)) return
        if (psi > phi) then
            call item%fail(error, item%path//".psi = "//fmt_real(psi)//" deg is above " &
                //item%path//".phi = "//fmt_real(phi)//" deg: the dilatancy angle must be >= 0 " &
                //"and <= phi = "//fmt_real(phi)//" [deg]")
            return
        end if
        call item%get_real("tension_cutoff", cutoff, error, at_least=0.0_wp, &
            unit="Pa", found=found)
        if (allocated(error)) return
        if (found .and. phi > 0.0_wp) then
            ! the cone ends at the mean stress c / tan(phi): no stress state lies beyond it
            apex = c/tan(phi*degree)
            if (cutoff > apex) then
                limit = fmt_below(apex, cutoff)
                call item%fail(error, item%path//".tension_cutoff = "//fmt_real(cutoff) &
                    //" Pa is above the apex of the yield surface, c / tan(phi) = "//limit &
                    //" Pa (c = "//fmt_real(c)//" Pa, phi = "//fmt_real(phi)//" deg): must " &
                    //"be >= 0 and <= "//limit//" [Pa]")
                return
            end if
        end if
        mat%friction = phi*degree
        mat%cohesion = c
        mat%dilatancy = psi*degree
        mat%tension_cutoff = cutoff
        call item%get_bool("separation", mat%separation, error)
        if (allocated(error)) return
        if (mat%separation .and. c > 0.0_wp .and. cutoff /= 0.0_wp) then
            call item%fail(error, item%path//".separation = true needs a stress-free apex: " &
                //"c = "//fmt_real(c)//" Pa here; give c = 0 or tension_cutoff = 0, or set " &
                //"separation to false")
            return
        end if
        call read_softening(item, phi, c, psi, mat, error)
        if (allocated(error)) return
    end subroutine read_strength

    !> `materials[i].softening`: residual strength and the plastic shear strain that reaches
    !> it. Residual values default to the peak values (psi_residual to 0) and never exceed them.
    subroutine read_softening(item, phi, c, psi, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        real(wp), intent(in) :: phi
            !! peak friction angle [deg]
        real(wp), intent(in) :: c
            !! peak cohesion [Pa]
        real(wp), intent(in) :: psi
            !! peak dilatancy angle [deg]
        type(strength_type), intent(inout) :: mat
            !! strength being resolved (peak values set)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: softening
        character(len=:), allocatable :: spath
        logical :: found
        integer :: k
        real(wp) :: phi_r, c_r, psi_r

        ! without softening the residual values are the peak values
        mat%softening = softening_none
        mat%friction_residual = mat%friction
        mat%cohesion_residual = mat%cohesion
        mat%dilatancy_residual = mat%dilatancy
        call item%get_section("softening", softening_keys, softening, error, &
            found=found)
        if (allocated(error) .or. .not. found) return
        spath = softening%path
        call softening%get_choice("type", softening_names, [softening_none, &
            softening_linear, softening_exponential], mat%softening, error, required=.true.)
        if (allocated(error)) return
        if (mat%softening == softening_none) then
            do k = 2, size(softening_keys)
                if (softening%has(trim(softening_keys(k)))) then
                    call item%fail(error, spath//"."//trim(softening_keys(k)) &
                        //' only applies to softening.type = "linear" or "exponential" ' &
                        //'(here "none"); remove it')
                    return
                end if
            end do
            return
        end if
        phi_r = phi
        c_r = c
        psi_r = 0.0_wp
        call softening%get_real("phi_residual", phi_r, error, at_least=0.0_wp, &
            unit="deg")
        if (allocated(error)) return
        call check_residual(item, spath//".phi_residual", phi_r, item%path//".phi", phi, "deg", error)
        if (allocated(error)) return
        call softening%get_real("c_residual", c_r, error, at_least=0.0_wp, &
            unit="Pa")
        if (allocated(error)) return
        call check_residual(item, spath//".c_residual", c_r, item%path//".c", c, "Pa", error)
        if (allocated(error)) return
        call softening%get_real("psi_residual", psi_r, error, at_least=0.0_wp, &
            unit="deg")
        if (allocated(error)) return
        call check_residual(item, spath//".psi_residual", psi_r, item%path//".psi", psi, "deg", error)
        if (allocated(error)) return
        if (psi_r > phi_r) then
            call item%fail(error, spath//".psi_residual = "//fmt_real(psi_r)//" deg " &
                //"is above the residual friction angle "//fmt_real(phi_r)//" deg: the " &
                //"dilatancy angle must be >= 0 and <= phi, also at residual strength [deg]")
            return
        end if
        if (phi_r == 0.0_wp .and. c_r == 0.0_wp) then
            call item%fail(error, spath//": phi_residual = 0 and c_residual = 0 leave " &
                //"no strength once softened; keep phi_residual > 0 [deg] or c_residual > 0 " &
                //"[Pa] (a material without strength is a newtonian fluid)")
            return
        end if
        call softening%get_real("strain", mat%softening_strain, error, &
            required=.true., above=0.0_wp)
        if (allocated(error)) return
        mat%friction_residual = phi_r*degree
        mat%cohesion_residual = c_r
        mat%dilatancy_residual = psi_r*degree
    end subroutine read_softening

    !> The strength divided by a factor F, as the strength reduction method does (Dawson,
    !> Roth and Drescher 1999; Griffiths and Lane 1999): tan(phi_F) = tan(phi) / F,
    !> c_F = c / F, the tensile strength / F, the same for the residual values; the dilatancy
    !> angle keeps psi <= phi: psi_F = min(psi, phi_F) (the non-associated flow of the case is
    !> kept, and an associated one stays associated). F = 1 leaves the strength unchanged.
    pure function reduced_strength(strength, factor) result(reduced)
        type(strength_type), intent(in) :: strength
            !! the strength of the case
        real(wp), intent(in) :: factor
            !! strength reduction factor F > 0 [-]
        type(strength_type) :: reduced

        reduced = strength
        if (factor == 1.0_wp) return
        reduced%friction = atan(tan(strength%friction)/factor)
        reduced%cohesion = strength%cohesion/factor
        reduced%dilatancy = min(strength%dilatancy, reduced%friction)
        if (strength%tension_cutoff > 0.0_wp) reduced%tension_cutoff = strength%tension_cutoff/factor
        reduced%friction_residual = atan(tan(strength%friction_residual)/factor)
        reduced%cohesion_residual = strength%cohesion_residual/factor
        reduced%dilatancy_residual = min(strength%dilatancy_residual, reduced%friction_residual)
    end function reduced_strength

    !> Refuse a residual strength parameter above its peak value.
    subroutine check_residual(item, key, residual, peak_key, peak, unit, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        character(len=*), intent(in) :: key
            !! full key path of the residual value
        real(wp), intent(in) :: residual
            !! residual value [unit]
        character(len=*), intent(in) :: peak_key
            !! full key path of the peak value
        real(wp), intent(in) :: peak
            !! peak value [unit]
        character(len=*), intent(in) :: unit
            !! unit of both values
        type(error_type), allocatable, intent(out) :: error
            !! set when residual > peak

        if (residual > peak) then
            call item%fail(error, key//" = "//fmt_real(residual)//" "//unit//" is " &
                //"above the peak value "//peak_key//" = "//fmt_real(peak)//" "//unit &
                //": residual strength above peak; must be >= 0 and <= "//fmt_real(peak) &
                //" ["//unit//"]")
        end if
    end subroutine check_residual

end module mpm_strength
