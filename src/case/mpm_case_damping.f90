!> The `damping` key of a case: local or kinetic damping.
module mpm_case_damping
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: damping_section_type, read_damping, damping_keys
    public :: damping_none, damping_local, damping_kinetic, damping_names

    ! Damping
    integer, parameter :: damping_none = 0     !! no damping
    integer, parameter :: damping_local = 1    !! local (Cundall) damping of nodal forces
    integer, parameter :: damping_kinetic = 2  !! kinetic damping (dynamic relaxation)
    character(len=*), parameter :: damping_names(0:2) = &
        [character(len=7) :: "none", "local", "kinetic"]
        !! name of each damping type in the case file

    character(len=*), parameter :: damping_keys(*) = [character(len=5) :: "type", "value"]
        !! keys of `damping`

    !> `damping`: which damping, and its coefficient.
    type :: damping_section_type
        integer :: type = damping_none
            !! damping type
        real(wp) :: value = 0.0_wp
            !! local damping coefficient alpha [-] (0 <= alpha < 1)
    end type damping_section_type

contains

    !> `damping`: type, and the coefficient of local damping.
    subroutine read_damping(root, damping, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(damping_section_type), intent(inout) :: damping
            !! the damping section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found

        call root%get_section("damping", damping_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_choice("type", damping_names, [damping_none, damping_local, &
            damping_kinetic], damping%type, error)
        if (allocated(error)) return
        if (damping%type == damping_local) then
            call cur%get_real("value", damping%value, error, required=.true., at_least=0.0_wp, &
                below=1.0_wp)
        else if (cur%has("value")) then
            call cur%fail(error, 'damping.value only applies to damping.type = "local"' &
                //' (here "'//trim(damping_names(damping%type))//'"); remove it')
        end if
    end subroutine read_damping

end module mpm_case_damping
