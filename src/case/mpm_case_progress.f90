!> The `progress` key of a case: how often the run reports its progress.
module mpm_case_progress
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type
    implicit none
    private
    public :: progress_section_type, read_progress, progress_keys

    character(len=*), parameter :: progress_keys(*) = [character(len=8) :: "interval"]
        !! keys of `progress`

    !> `progress`: the progress lines of a run.
    type :: progress_section_type
        real(wp) :: interval = 2.0_wp
            !! wall-clock seconds between progress lines [s]
    end type progress_section_type

contains

    !> `progress`: wall-clock seconds between progress lines.
    subroutine read_progress(root, progress, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(progress_section_type), intent(inout) :: progress
            !! the progress section
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found

        call root%get_section("progress", progress_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_real("interval", progress%interval, error, above=0.0_wp, unit="s")
    end subroutine read_progress

end module mpm_case_progress
