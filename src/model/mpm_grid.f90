!> The background grid: a regular Cartesian grid of nodes with nodal fields.
!>
!> Nodes are numbered lexicographically, x fastest: node (i, j, k) (0-based) has the index
!> 1 + i + nn(1) * (j + nn(2) * k). In 2D nn(3) = 1 and k = 0.
module mpm_grid
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_case, only: case_type
    implicit none
    private
    public :: grid_type, new_grid, node_index, node_position

    !> Geometry of the grid and the nodal fields of one step.
    type :: grid_type
        integer :: dim = 2
            !! space dimensions
        integer :: ncells(3) = 1
            !! cells per direction (1 in z for 2D)
        integer :: nn(3) = 1
            !! nodes per direction (ncells + 1; 1 in z for 2D)
        integer :: nnodes = 0
            !! total number of nodes
        real(wp) :: dx = 0.0_wp
            !! cell size [m]
        real(wp) :: origin(3) = 0.0_wp
            !! position of node (0, 0, 0) [m]
        integer :: bc(2, 3) = 0
            !! boundary condition of each face, as case%bc
        real(wp), allocatable :: mass(:)
            !! nodal mass (nnodes) [kg]
        real(wp), allocatable :: momentum(:, :)
            !! nodal momentum (dim, nnodes) [kg m/s]
        real(wp), allocatable :: fint(:, :)
            !! internal force (dim, nnodes) [N]
        real(wp), allocatable :: fext(:, :)
            !! external (body) force (dim, nnodes) [N]
        real(wp), allocatable :: velocity(:, :)
            !! nodal velocity after the update (dim, nnodes) [m/s]
        real(wp), allocatable :: acceleration(:, :)
            !! nodal acceleration of the step (dim, nnodes) [m/s2]
        logical, allocatable :: constrained(:, :)
            !! velocity component held at zero by a boundary condition (dim, nnodes)
    end type grid_type

contains

    !> Build the grid of a case, with its boundary constraints.
    subroutine new_grid(grid, case, error)
        type(grid_type), intent(out) :: grid
            !! grid to create
        type(case_type), intent(in) :: case
            !! resolved case
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        integer :: stat, i, j, k, a, id, ijk(3), d
        character(len=256) :: msg

        grid%dim = case%dim
        grid%ncells = 1
        grid%ncells(1:case%dim) = case%ncells(1:case%dim)
        grid%nn = 1
        grid%nn(1:case%dim) = grid%ncells(1:case%dim) + 1
        grid%nnodes = product(grid%nn)
        grid%dx = case%dx
        grid%origin = case%origin
        grid%bc = case%bc
        d = case%dim
        allocate (grid%mass(grid%nnodes), grid%momentum(d, grid%nnodes), &
            grid%fint(d, grid%nnodes), grid%fext(d, grid%nnodes), &
            grid%velocity(d, grid%nnodes), grid%acceleration(d, grid%nnodes), &
            grid%constrained(d, grid%nnodes), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the grid: "//trim(msg), exit_other)
            return
        end if
        grid%mass = 0.0_wp
        grid%momentum = 0.0_wp
        grid%fint = 0.0_wp
        grid%fext = 0.0_wp
        grid%velocity = 0.0_wp
        grid%acceleration = 0.0_wp
        grid%constrained = .false.
        ! 1 = sliding (normal component held), 2 = fixed (all components held)
        do k = 0, grid%nn(3) - 1
            do j = 0, grid%nn(2) - 1
                do i = 0, grid%nn(1) - 1
                    ijk = [i, j, k]
                    id = node_index(grid, ijk)
                    do a = 1, d
                        if (ijk(a) == 0) call constrain(grid%bc(1, a), a, id)
                        if (ijk(a) == grid%nn(a) - 1) call constrain(grid%bc(2, a), a, id)
                    end do
                end do
            end do
        end do

    contains

        subroutine constrain(kind, axis, node)
            integer, intent(in) :: kind, axis, node
            select case (kind)
            case (1)
                grid%constrained(axis, node) = .true.
            case (2)
                grid%constrained(:, node) = .true.
            case default
                continue
            end select
        end subroutine constrain

    end subroutine new_grid

    !> Linear index of node (i, j, k), 0-based per direction.
    pure integer function node_index(grid, ijk)
        type(grid_type), intent(in) :: grid
            !! grid
        integer, intent(in) :: ijk(3)
            !! 0-based node coordinates
        node_index = 1 + ijk(1) + grid%nn(1)*(ijk(2) + grid%nn(2)*ijk(3))
    end function node_index

    !> Position of node `id` [m].
    pure function node_position(grid, id) result(x)
        type(grid_type), intent(in) :: grid
            !! grid
        integer, intent(in) :: id
            !! linear node index
        real(wp) :: x(3)
            !! node position, z = origin(3) in 2D [m]

        integer :: r, ijk(3)

        r = id - 1
        ijk(1) = mod(r, grid%nn(1))
        r = r/grid%nn(1)
        ijk(2) = mod(r, grid%nn(2))
        ijk(3) = r/grid%nn(2)
        x = grid%origin + grid%dx*real(ijk, wp)
    end function node_position

end module mpm_grid
