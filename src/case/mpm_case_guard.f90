!> The `guard` key of a case: the blow-up guard's energy bound and its healthy copies.
module mpm_case_guard
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: guard_section_type, read_guard, guard_keys, snapshot_in_file, snapshot_in_memory

    character(len=*), parameter :: guard_keys(*) = [character(len=14) :: "energy_factor", &
        "snapshot_steps", "snapshot_in"]
        !! keys of `guard`
    integer, parameter :: snapshot_in_file = 1
        !! the copies go to a file of the output folder (.last_healthy.h5)
    integer, parameter :: snapshot_in_memory = 2
        !! the copies stay in memory (the particle arrays a second time)

    !> `guard`: when the blow-up guard stops a run, and its copies of the healthy state.
    type :: guard_section_type
        real(wp) :: energy_factor = 1.0_wp
            !! the blow-up guard stops a run that created more energy (its energy residual)
            !! than this factor times its energy scale (initial kinetic and elastic energy,
            !! |work of gravity and loads| so far) [-]
        integer :: snapshot_steps = 100
            !! steps between two copies of the state kept in memory, written as the last
            !! healthy state when the guard stops the run; 0: no copy
        integer :: snapshot_in = snapshot_in_file
            !! where the copies are kept: snapshot_in_file (a checkpoint in the output folder,
            !! renamed last_healthy.h5 when the guard stops the run) or snapshot_in_memory
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
        if (allocated(error)) return
        call cur%get_choice("snapshot_in", [character(len=6) :: "file", "memory"], &
            [snapshot_in_file, snapshot_in_memory], guard%snapshot_in, error)
    end subroutine read_guard

end module mpm_case_guard
