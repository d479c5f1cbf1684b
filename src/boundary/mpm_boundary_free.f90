!> A free face: no constraint, the material may leave the domain through it.
module mpm_boundary_free
    use mpm_boundary, only: boundary_type, face_nodes_type, boundary_key_width
    implicit none
    private
    public :: free_boundary_type

    !> No constraint.
    type, extends(boundary_type) :: free_boundary_type
    contains
        procedure, nopass :: names => free_names
        procedure :: nodes => free_nodes
    end type free_boundary_type

contains

    !> "free"
    pure subroutine free_names(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=boundary_key_width) :: "free"]
    end subroutine free_names

    !> Nothing held, no contact, particles may leave.
    pure function free_nodes(self, axis, dim) result(nodes)
        class(free_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        type(face_nodes_type) :: nodes
            !! its action on the face's nodes

        nodes = face_nodes_type()
    end function free_nodes

end module mpm_boundary_free
