!> The `guard` key of a case: the blow-up guard's energy bound and its healthy copies.
module mpm_case_guard
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: guard_section_type, read_guard, guard_keys

    character(len=*), parameter :: guard_keys(*) = [character(len=14) :: "energy_factor", &
        "snapshot_steps"]
        !! keys of `guard`

    !> `guard`: when the blow-up guard stops a run, and its copies of the healthy state.
    type :: guard_section_type
        real(wp) :: energy_factor = 1.0_wp
            !! the blow-up guard stops a run that created more energy (its energy residual)
            !! than this factor times its energy scale (initial kinetic and elastic energy,
            !! |work of gravity and loads| so far) [-]
        integer :: snapshot_steps = 100
            !! steps between two copies of the state kept in memory, written as the last
            !! healthy state when the guard stops the run; 0: no copy
    end type guard_section_type

contains

    !> `guard`: the blow-up guard's energy bound and its copies of the healthy state.
    subroutine read_guard(root, guard, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(guard_section_type), intent(inout) :: guard
            !! the guard section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found

        call root%get_section("guard", guard_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_real("energy_factor", guard%energy_factor, error, above=0.0_wp)
        if (allocated(error)) return
        call cur%get_int("snapshot_steps", guard%snapshot_steps, error, at_least=0)
    end subroutine read_guard

end module mpm_case_guard
