!> The `save_state` and `load_state` keys of a case: state files to write at the end and to
!> start from.
module mpm_case_states
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type, room_written
    implicit none
    private
    public :: read_states

contains

    !> `save_state` and `load_state`: state files to write at the end and to start from.
    subroutine read_states(root, save_state, load_state, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        character(len=:), allocatable, intent(inout) :: save_state
            !! state file to write at the end ("" for none)
        character(len=:), allocatable, intent(inout) :: load_state
            !! state file to start from ("" for none)
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        logical :: found, exists

        call root%get_path("save_state", room_written, save_state, error)
        if (allocated(error)) return
        call root%get_path("load_state", 0, load_state, error, found=found)
        if (allocated(error) .or. .not. found) return
        inquire (file=load_state, exist=exists)
        if (.not. exists) then
            call root%fail(error, "load_state: file '"//load_state//"' not found " &
                //"(a relative path is taken from the current working directory)")
        end if
    end subroutine read_states

end module mpm_case_states
