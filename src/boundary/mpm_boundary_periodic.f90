!> A periodic face: tied to the opposite face, whose nodes are its own (both faces of an axis
!> are periodic). A laterally infinite layer, one cell wide or more: the 1D shear column of
!> site response and S waves, an infinite slope.
!>
!> The grid lists the pairs of nodes of the two faces (mpm_grid: the node of the upper face
!> is slaved to the one of the lower face); after each scatter the solver adds the upper
!> node's mass, momentum and forces to the lower one, and after each nodal update gives it
!> the lower one's velocity and acceleration (mpm_step_passes), so both faces move as one. A
!> particle that leaves through one face comes back through the other.
module mpm_boundary_periodic
    use mpm_boundary, only: boundary_type, face_nodes_type, boundary_key_width
    implicit none
    private
    public :: periodic_boundary_type

    !> Tied to the opposite face.
    type, extends(boundary_type) :: periodic_boundary_type
    contains
        procedure, nopass :: names => periodic_names
        procedure :: nodes => periodic_nodes
    end type periodic_boundary_type

contains

    !> "periodic"
    pure subroutine periodic_names(list)
        character(len=boundary_key_width), allocatable, intent(out) :: list(:)
            !! the names

        list = [character(len=boundary_key_width) :: "periodic"]
    end subroutine periodic_names

    !> Nothing held: the face's nodes are tied to the opposite face's.
    pure function periodic_nodes(self, axis, dim) result(nodes)
        class(periodic_boundary_type), intent(in) :: self
            !! the condition
        integer, intent(in) :: axis
            !! axis normal to the face
        integer, intent(in) :: dim
            !! space dimensions
        type(face_nodes_type) :: nodes
            !! its action on the face's nodes

        nodes%periodic = .true.
    end function periodic_nodes

end module mpm_boundary_periodic
