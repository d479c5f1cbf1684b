!> The regions of `prescribed_motion` (mpm_case_motion) on the grid of a step.
!>
!> At the start of each step the nodes inside each region's box at that time (its corners
!> moved by the region's displacement v F(t)) are held along the region's components at its
!> velocity v f(t): the nodal update leaves their force out of those components, sums the
!> impulse that takes per region (mpm_kernel_nodal::prescribed_impulses, the region's
!> reaction, with its work booked as load work) and sets their velocity
!> (mpm_kernel_nodal::set_prescribed), as for a velocity face. At the end of the step the
!> nodes get back the constraints of their faces.
module mpm_motion
    use, intrinsic :: iso_fortran_env, only: output_unit
    use mpm_kinds, only: wp
    use mpm_strings, only: int_text, fmt_vector, fmt_real
    use mpm_error, only: error_type, fatal_error, exit_input
    use mpm_case, only: case_type
    use mpm_grid, only: grid_type
    implicit none
    private
    public :: hold_regions, release_regions, region_displacement, region_count, half_cell_notes

    character(len=*), parameter :: axis_names = "xyz"

contains

    !> Number of regions of prescribed_motion of a case.
    pure integer function region_count(case)
        type(case_type), intent(in) :: case
            !! the case

        region_count = 0
        if (allocated(case%motions)) region_count = size(case%motions)
    end function region_count

    !> The displacement of region r at time t: v F(t) along its held components [m].
    pure function region_displacement(case, r, t) result(d)
        type(case_type), intent(in) :: case
            !! the case
        integer, intent(in) :: r
            !! the region
        real(wp), intent(in) :: t
            !! time [s]
        real(wp) :: d(3)

        associate (motion => case%motions(r))
            d = merge(motion%velocity*motion%time%integral(t), 0.0_wp, motion%held)
        end associate
    end function region_displacement

    !> Hold the nodes of every region at time t (the step's start) for the step. A region
    !> that would move a component a face holds (a fixed or sliding face, a velocity face) is
    !> an error: the two contradict each other.
    subroutine hold_regions(case, grid, t, error)
        type(case_type), intent(in) :: case
            !! the case
        type(grid_type), intent(inout) :: grid
            !! the grid of the step
        real(wp), intent(in) :: t
            !! time of the step's start [s]
        type(error_type), allocatable, intent(out) :: error
            !! set when a region contradicts a face

        integer :: r, n, dim, lo(3), hi(3), i, j, k, id, count
        real(wp) :: shift(3), factor

        grid%nregion_nodes = 0
        if (region_count(case) == 0) return
        dim = grid%dim
        if (.not. allocated(grid%region_velocity)) then
            allocate (grid%region_velocity(dim, size(case%motions)), &
                grid%region_held(dim, size(case%motions)), &
                grid%region_impulse(dim, size(case%motions)))
            grid%region_impulse = 0.0_wp
        end if
        ! the nodes of each region's box: count, then list
        count = 0
        do r = 1, size(case%motions)
            call region_box(r, lo, hi)
            count = count + product(max(0, hi(1:dim) - lo(1:dim) + 1))
        end do
        if (allocated(grid%region_node)) then
            if (size(grid%region_node) < count) deallocate (grid%region_node, grid%region_of, &
                grid%region_saved)
        end if
        if (.not. allocated(grid%region_node)) allocate (grid%region_node(count), &
            grid%region_of(count), grid%region_saved(dim, count))
        n = 0
        do r = 1, size(case%motions)
            associate (motion => case%motions(r))
                factor = motion%time%factor(t)
                grid%region_velocity(:, r) = merge(motion%velocity(1:dim)*factor, 0.0_wp, &
                    motion%held(1:dim))
                grid%region_held(:, r) = motion%held(1:dim)
            end associate
            call region_box(r, lo, hi)
            do k = lo(3), hi(3)
                do j = lo(2), hi(2)
                    do i = lo(1), hi(1)
                        id = 1 + i + grid%nn(1)*(j + grid%nn(2)*k)
                        if (any(grid%constrained(:, id) .and. grid%region_held(:, r) .and. &
                            grid%region_velocity(:, r) /= 0.0_wp)) then
                            call contradiction(r, id)
                            call release_regions(grid)
                            return
                        end if
                        n = n + 1
                        grid%region_node(n) = id
                        grid%region_of(n) = r
                        grid%region_saved(:, n) = grid%constrained(:, id)
                        grid%constrained(:, id) = grid%constrained(:, id) .or. &
                            grid%region_held(:, r)
                        grid%nregion_nodes = n
                    end do
                end do
            end do
        end do
    contains
        !> The node index range (0-based, this grid) inside region r's box at time t.
        subroutine region_box(r, lo, hi)
            integer, intent(in) :: r
            integer, intent(out) :: lo(3), hi(3)

            shift = region_displacement(case, r, t)
            lo = 0
            hi = 0
            lo(1:dim) = max(0, ceiling((case%motions(r)%xmin(1:dim) + shift(1:dim) &
                - grid%origin(1:dim))/grid%dx - 1.0e-9_wp))
            hi(1:dim) = min(grid%nn(1:dim) - 1, floor((case%motions(r)%xmax(1:dim) &
                + shift(1:dim) - grid%origin(1:dim))/grid%dx + 1.0e-9_wp))
        end subroutine region_box

        !> The error of a region that moves a held component of a face's node.
        subroutine contradiction(r, id)
            integer, intent(in) :: r, id

            integer :: a, b, node(3)
            real(wp) :: x(3)
            character(len=:), allocatable :: faces

            node = [mod(id - 1, grid%nn(1)), mod((id - 1)/grid%nn(1), grid%nn(2)), &
                (id - 1)/(grid%nn(1)*grid%nn(2))]
            x = grid%origin + grid%dx*real(node, wp)
            do a = 1, dim
                if (grid%constrained(a, id) .and. grid%region_held(a, r) .and. &
                    grid%region_velocity(a, r) /= 0.0_wp) exit
            end do
            faces = ""
            do b = 1, dim
                if (node(b) == 0) faces = faces//" "//axis_names(b:b)//"min"
                if (node(b) == grid%nn(b) - 1) faces = faces//" "//axis_names(b:b)//"max"
            end do
            call fatal_error(error, case%file//": prescribed_motion["//int_text(r)//'] "' &
                //case%motions(r)%name//'" moves the node at '//fmt_vector(x(1:dim), 6) &
                //" m along "//axis_names(a:a)//", which domain.boundaries holds there (face" &
                //faces//"); give the region only the components the face leaves free " &
                //"(components), or keep its box off that face", exit_input)
        end subroutine contradiction
    end subroutine hold_regions

    !> Say once per region when it has moved half a cell: its box then holds the next row of
    !> nodes, and its reaction is no longer that of a rigid footing (docs/input.md).
    subroutine half_cell_notes(case, t, noted)
        type(case_type), intent(in) :: case
            !! the case
        real(wp), intent(in) :: t
            !! simulated time [s]
        logical, allocatable, intent(inout) :: noted(:)
            !! the regions already noted (allocated on the first call)

        integer :: r
        real(wp) :: moved

        if (.not. allocated(noted)) then
            allocate (noted(region_count(case)))
            noted = .false.
        end if
        do r = 1, size(noted)
            if (noted(r)) cycle
            moved = maxval(abs(region_displacement(case, r, t)))
            if (moved <= 0.5_wp*case%domain%dx) cycle
            noted(r) = .true.
            write (output_unit, "(a)") "mpm_geo: prescribed_motion["//int_text(r)//'] "' &
                //case%motions(r)%name//'" has moved '//fmt_real(moved, 4)//" m at t = " &
                //fmt_real(t, 6)//" s, more than half a cell (dx = "//fmt_real(case%domain%dx) &
                //" m): its box now holds the next row of nodes, and its reaction from here " &
                //"on is not that of a rigid body (docs/input.md, prescribed_motion)"
        end do
    end subroutine half_cell_notes

    !> Give the region nodes back the constraints of their faces (end of the step).
    subroutine release_regions(grid)
        type(grid_type), intent(inout) :: grid
            !! the grid of the step

        integer :: n

        do n = 1, grid%nregion_nodes
            grid%constrained(:, grid%region_node(n)) = grid%region_saved(:, n)
        end do
        grid%nregion_nodes = 0
    end subroutine release_regions

end module mpm_motion
