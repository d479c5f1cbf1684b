!> The strength keys Mohr-Coulomb and Drucker-Prager materials share: friction, cohesion,
!> dilatancy, tension cutoff, separation and softening.
module mpm_case_material_strength
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real, fmt_below
    use mpm_case_cursor, only: cursor_type
    use mpm_case_material_model, only: material_spec_type, key_width, degree, softening_none, &
        softening_linear, softening_exponential, softening_names
    implicit none
    private
    public :: read_strength, strength_keys, softening_keys

    character(len=*), parameter :: strength_keys(*) = [character(len=key_width) :: "phi", "c", &
        "psi", "tension_cutoff", "softening", "separation"]
        !! keys of the strength of a material
    character(len=*), parameter :: softening_keys(*) = [character(len=12) :: "type", &
        "phi_residual", "c_residual", "psi_residual", "strain"]
        !! keys of `materials[i].softening`

contains

    !> Strength of a Mohr-Coulomb or Drucker-Prager material: `phi`, `c`, `psi`,
    !> `tension_cutoff`, `separation` and `softening`. Angles are read in degrees and stored in
    !> radians.
    subroutine read_strength(item, family, mat, error)
        type(cursor_type), intent(in) :: item
            !! the material object
        character(len=*), intent(in) :: family
            !! "Mohr-Coulomb" or "Drucker-Prager", for messages
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved
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
        type(material_spec_type), intent(inout) :: mat
            !! material being resolved (peak values set)
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

end module mpm_case_material_strength
