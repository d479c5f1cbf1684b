!> A sliding face: the normal velocity is zero, the tangential one free (a smooth wall).
module mpm_boundary_sliding
    use mpm_boundary, only: boundary_type, face_nodes_type, boundary_key_width
    implicit none
    private
    public :: sliding_boundary_type

    !> Normal velocity held at zero.
    type, extends(boundary_type) :: sliding_boundary_type
    contains
        procedure, nopass :: names => sliding_names
        procedure :: nodes => sliding_nodes
    end type sliding_boundary_type

contains

    !> "sliding"
    pure subroutine sliding_names(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=boundary_key_width) :: "sliding"]
    end subroutine sliding_names

    !> The component along the face's axis held at zero; a wall.
    pure function sliding_nodes(self, axis, dim) result(nodes)
        class(sliding_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        type(face_nodes_type) :: nodes
            !! its action on the face's nodes

        nodes%held(axis) = .true.
        nodes%keeps_particles = .true.
    end function sliding_nodes

end module mpm_boundary_sliding
