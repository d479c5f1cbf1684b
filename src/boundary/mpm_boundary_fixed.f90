!> A fixed face: every velocity component zero (no slip, sticking).
module mpm_boundary_fixed
    use mpm_boundary, only: boundary_type, face_nodes_type, boundary_key_width
    implicit none
    private
    public :: fixed_boundary_type

    !> All velocity components held at zero.
    type, extends(boundary_type) :: fixed_boundary_type
    contains
        procedure, nopass :: names => fixed_names
        procedure :: nodes => fixed_nodes
    end type fixed_boundary_type

contains

    !> "fixed"
    pure subroutine fixed_names(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=boundary_key_width) :: "fixed"]
    end subroutine fixed_names

    !> Every component held at zero; a wall.
    pure function fixed_nodes(self, axis, dim) result(nodes)
        class(fixed_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        type(face_nodes_type) :: nodes
            !! its action on the face's nodes

        nodes%held(1:dim) = .true.
        nodes%keeps_particles = .true.
    end function fixed_nodes

end module mpm_boundary_fixed
