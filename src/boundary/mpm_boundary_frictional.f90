!> A frictional face: Coulomb friction with coefficient mu, no penetration, and the material
!> may separate from it (lift-off). Its nodes are contact pairs of the contact kernel.
module mpm_boundary_frictional
    use mpm_kinds, only: wp
    use mpm_error, only: error_type
    use mpm_strings, only: fmt_real
    use mpm_case_cursor, only: cursor_type
    use mpm_boundary, only: boundary_type, face_nodes_type, boundary_key_width
    implicit none
    private
    public :: frictional_boundary_type

    !> Coulomb friction with coefficient mu.
    type, extends(boundary_type) :: frictional_boundary_type
        real(wp) :: mu = 0.0_wp
            !! Coulomb friction coefficient [-]
    contains
        procedure, nopass :: names => frictional_names
        procedure, nopass :: keys => frictional_keys
        procedure, nopass :: example => frictional_example
        procedure, nopass :: purpose => frictional_purpose
        procedure, nopass :: needs => frictional_needs
        procedure :: read => frictional_read
        procedure :: summary => frictional_summary
        procedure :: nodes => frictional_nodes
    end type frictional_boundary_type

contains

    !> "frictional"
    pure subroutine frictional_names(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=boundary_key_width) :: "frictional"]
    end subroutine frictional_names

    !> "mu"
    pure subroutine frictional_keys(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the keys

        list = [character(len=boundary_key_width) :: "mu"]
    end subroutine frictional_keys

    !> The object form, for messages.
    pure function frictional_example() result(text)
        character(len=:), allocatable :: text
            !! an example face object

        text = '{"type": "frictional", "mu": 0.4}'
    end function frictional_example

    !> What it is for, for messages.
    pure function frictional_purpose() result(text)
        character(len=:), allocatable :: text
            !! "a face with ..."

        text = "a face with Coulomb friction"
    end function frictional_purpose

    !> What the name alone lacks.
    pure function frictional_needs() result(text)
        character(len=:), allocatable :: text
            !! the missing parameter

        text = "a friction coefficient"
    end function frictional_needs

    !> `mu`, required, >= 0.
    subroutine frictional_read(self, face, dim, error)
        class(frictional_boundary_type), intent(inout) :: self
            !! the condition
        type(cursor_type), intent(in) :: face
            !! the face object, its keys checked
        integer, intent(in) :: dim
            !! space dimensions
        type(error_type), allocatable, intent(out) :: error
            !! first error found

        call face%get_real("mu", self%mu, error, required=.true., at_least=0.0_wp)
    end subroutine frictional_read

    !> " (mu = 0.4)"
    pure function frictional_summary(self) result(text)
        class(frictional_boundary_type), intent(in) :: self
            !! the condition
        character(len=:), allocatable :: text
            !! the words after the name

        text = " (mu = "//fmt_real(self%mu)//")"
    end function frictional_summary

    !> Its nodes are contact pairs with its mu; a wall.
    pure function frictional_nodes(self, axis, dim) result(nodes)
        class(frictional_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        type(face_nodes_type) :: nodes
            !! its action on the face's nodes

        nodes%contact = .true.
        nodes%mu = self%mu
        nodes%keeps_particles = .true.
    end function frictional_nodes

end module mpm_boundary_frictional
