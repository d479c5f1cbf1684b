!> The `strength_reduction` key of a case: a factor-of-safety analysis by strength reduction.
!>
!> The case is run several times from its start (the same initial state: K0 stresses of the
!> case's own strength, or unstressed ground under gravity), each time with the strength of
!> every material that has one divided by a trial factor F (tan(phi) / F, c / F, Su / F;
!> `material_type%reduce_strength`). A trial fails when the largest particle displacement
!> at tend exceeds `displacement_limit`, or when the ground is still moving at tend (its
!> kinetic energy above `rest_ratio` times the largest it reached). Bisection between
!> `factor_min` (which must hold) and `factor_max` (which must fail) narrows the factor of
!> safety to `tolerance`. Dawson, Roth and Drescher (1999), Griffiths and Lane (1999).
module mpm_case_strength_reduction
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_case_materials, only: material_spec_type
    implicit none
    private
    public :: strength_reduction_section_type, read_strength_reduction, strength_reduction_keys
    public :: strength_reduction_line

    character(len=*), parameter :: strength_reduction_keys(*) = [character(len=18) :: &
        "factor_min", "factor_max", "tolerance", "displacement_limit", "rest_ratio"]
        !! keys of `strength_reduction`

    !> `strength_reduction`: the bracket of the factor, the tolerance and the failure criterion.
    type :: strength_reduction_section_type
        logical :: enabled = .false.
            !! the case asks for a factor of safety
        real(wp) :: factor_min = 1.0_wp
            !! smallest factor tried: the ground must hold there [-]
        real(wp) :: factor_max = 3.0_wp
            !! largest factor tried: the ground must fail there [-]
        real(wp) :: tolerance = 0.01_wp
            !! width of the final bracket of the factor [-]
        real(wp) :: displacement_limit = 0.0_wp
            !! a trial whose largest particle displacement at tend exceeds it fails [m]
        real(wp) :: rest_ratio = 1.0e-3_wp
            !! a trial whose kinetic energy at tend exceeds this fraction of its peak fails
            !! (still moving) [-]
    end type strength_reduction_section_type

contains

    !> `strength_reduction`: optional; the bracket, the tolerance and the criterion, checked,
    !> and at least one material with a strength to reduce.
    subroutine read_strength_reduction(root, materials, section, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(material_spec_type), intent(in) :: materials(:)
            !! the materials of the case
        type(strength_reduction_section_type), intent(inout) :: section
            !! the section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found, reduced
        integer :: i
        type(material_spec_type) :: copy

        call root%get_section("strength_reduction", strength_reduction_keys, cur, error, &
            found=found)
        if (allocated(error) .or. .not. found) return
        section%enabled = .true.
        if (root%has("save_state")) then
            call cur%fail(error, "strength_reduction runs the case once per trial; save_state " &
                //"would write every trial's state over the last one: remove save_state (each " &
                //"trial's particles are in its folder)")
            return
        end if
        call cur%get_real("factor_min", section%factor_min, error, above=0.0_wp)
        if (allocated(error)) return
        call cur%get_real("factor_max", section%factor_max, error, above=section%factor_min)
        if (allocated(error)) return
        call cur%get_real("tolerance", section%tolerance, error, above=0.0_wp, &
            below=section%factor_max - section%factor_min)
        if (allocated(error)) return
        call cur%get_real("displacement_limit", section%displacement_limit, error, &
            required=.true., above=0.0_wp, unit="m")
        if (allocated(error)) return
        call cur%get_real("rest_ratio", section%rest_ratio, error, above=0.0_wp, below=1.0_wp)
        if (allocated(error)) return
        reduced = .false.
        do i = 1, size(materials)
            if (.not. allocated(materials(i)%law)) cycle
            copy = materials(i)
            call copy%law%reduce_strength(2.0_wp, found)
            reduced = reduced .or. found
        end do
        if (.not. reduced) then
            call cur%fail(error, cur%path//": no material of the case has a shear strength " &
                //"to reduce (a strength reduction divides tan(phi) and c, or Su, by the " &
                //'factor); give the soil a type with one, e.g. "mohr_coulomb"')
        end if
    end subroutine read_strength_reduction

    !> The --check line of the section.
    function strength_reduction_line(section) result(line)
        type(strength_reduction_section_type), intent(in) :: section
            !! the section
        character(len=:), allocatable :: line

        line = "factor of safety by strength reduction between "//fmt_real(section%factor_min) &
            //" and "//fmt_real(section%factor_max)//" to "//fmt_real(section%tolerance) &
            //"; a trial fails above "//fmt_real(section%displacement_limit) &
            //" m of displacement or when its kinetic energy at tend exceeds " &
            //fmt_real(section%rest_ratio)//" of its peak"
    end function strength_reduction_line

end module mpm_case_strength_reduction
