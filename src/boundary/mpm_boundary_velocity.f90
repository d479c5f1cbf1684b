!> A face that moves the material at a prescribed velocity (a footing, a loading plate): every
!> velocity component of its nodes is held at the face's velocity, constant in time. The
!> impulse that takes is the face's reaction: summed per face (history.csv) and its work
!> entering the energy balance as work of the loads.
module mpm_boundary_velocity
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_vector
    use mpm_case_cursor, only: cursor_type
    use mpm_boundary, only: boundary_type, face_nodes_type, boundary_key_width
    implicit none
    private
    public :: velocity_boundary_type

    !> Every velocity component held at a prescribed value.
    type, extends(boundary_type) :: velocity_boundary_type
        real(wp) :: velocity(3) = 0.0_wp
            !! velocity of the face's nodes (1..dim) [m/s]
        integer :: dim = 2
            !! space dimensions (components of velocity)
    contains
        procedure, nopass :: names => velocity_names
        procedure, nopass :: keys => velocity_keys
        procedure, nopass :: example => velocity_example
        procedure, nopass :: purpose => velocity_purpose
        procedure, nopass :: needs => velocity_needs
        procedure :: read => velocity_read
        procedure :: summary => velocity_summary
        procedure :: nodes => velocity_nodes
    end type velocity_boundary_type

contains

    !> "velocity"
    pure subroutine velocity_names(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=boundary_key_width) :: "velocity"]
    end subroutine velocity_names

    !> "velocity"
    pure subroutine velocity_keys(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=boundary_key_width) :: "velocity"]
    end subroutine velocity_keys

    !> The object form, for messages.
    pure function velocity_example() result(text)
        character(len=:), allocatable :: text
            !! an example face object

        text = '{"type": "velocity", "velocity": [0, -0.01]}'
    end function velocity_example

    !> What it is for, for messages.
    pure function velocity_purpose() result(text)
        character(len=:), allocatable :: text
            !! "a face ..."

        text = "a face moving at a prescribed velocity"
    end function velocity_purpose

    !> What the name alone lacks.
    pure function velocity_needs() result(text)
        character(len=:), allocatable :: text
            !! the missing parameter

        text = "a velocity"
    end function velocity_needs

    !> `velocity`, required: dim finite numbers [m/s].
    subroutine velocity_read(self, face, dim, error)
        class(velocity_boundary_type), intent(inout) :: self
            !! the condition
        type(cursor_type), intent(in) :: face
            !! the face object, its keys checked
        integer, intent(in) :: dim
            !! space dimensions
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        self%dim = dim
        call face%get_vector("velocity", dim, self%velocity, error, required=.true., &
            unit="m/s")
    end subroutine velocity_read

    !> " (velocity = (0, -0.01) m/s)"
    pure function velocity_summary(self) result(text)
        class(velocity_boundary_type), intent(in) :: self
            !! the condition
        character(len=:), allocatable :: text
            !! the words after the name

        text = " (velocity = "//fmt_vector(self%velocity(1:self%dim))//" m/s)"
    end function velocity_summary

    !> Every component held at the face's velocity, the reaction booked; a wall.
    pure function velocity_nodes(self, axis, dim) result(nodes)
        class(velocity_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        type(face_nodes_type) :: nodes
            !! its action on the face's nodes

        nodes%held(1:dim) = .true.
        nodes%velocity(1:dim) = self%velocity(1:dim)
        nodes%prescribed = .true.
        nodes%keeps_particles = .true.
    end function velocity_nodes

end module mpm_boundary_velocity
