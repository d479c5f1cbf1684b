!> The `checkpoint` key of a case: when to write the state of the run for a restart.
module mpm_case_checkpoint
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_case_cursor, only: cursor_type, room_written
    implicit none
    private
    public :: checkpoint_section_type, read_checkpoint, checkpoint_keys

    character(len=*), parameter :: checkpoint_keys(*) = [character(len=13) :: "every_steps", &
        "every_minutes", "file", "on_signal"]
        !! keys of `checkpoint`

    !> `checkpoint`: when and where the run writes checkpoints.
    type :: checkpoint_section_type
        integer :: every_steps = 0
            !! steps between two checkpoints; 0: none by step count
        real(wp) :: every_minutes = 0.0_wp
            !! wall-clock minutes between two checkpoints; 0: none by wall time [min]
        character(len=:), allocatable :: file
            !! checkpoint file; "" for <output_dir>/checkpoint.h5
        logical :: on_signal = .true.
            !! on SIGTERM or SIGINT, write a checkpoint and stop (exit_interrupted)
    end type checkpoint_section_type

contains

    !> `checkpoint`: when to write the state of the run for a restart, and where.
    subroutine read_checkpoint(root, checkpoint, error)
        type(cursor_type), intent(in) :: root
            !! top-level object
        type(checkpoint_section_type), intent(inout) :: checkpoint
            !! the checkpoint section (file set to "")
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        type(cursor_type) :: cur
        logical :: found

        call root%get_section("checkpoint", checkpoint_keys, cur, error, found=found)
        if (allocated(error) .or. .not. found) return
        call cur%get_int("every_steps", checkpoint%every_steps, error, at_least=1)
        if (allocated(error)) return
        call cur%get_real("every_minutes", checkpoint%every_minutes, error, above=0.0_wp, &
            unit="min")
        if (allocated(error)) return
        call cur%get_path("file", room_written, checkpoint%file, error)
        if (allocated(error)) return
        call cur%get_bool("on_signal", checkpoint%on_signal, error)
    end subroutine read_checkpoint

end module mpm_case_checkpoint
