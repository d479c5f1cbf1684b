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
    use mpm_particles, only: particles_type
    use mpm_stencil, only: stencils_type
    implicit none
    private
    public :: hold_regions, release_regions, region_displacement, region_count, half_cell_notes, &
        body_displacement, has_rigid_bodies

    character(len=*), parameter :: axis_names = "xyz"
    real(wp), parameter :: min_fill = 0.2_wp
        !! a rigid body moves the nodes whose cell it fills to a fifth at least: the volume
        !! of its particles weighted by the node's shape function, sum_p N_ip V_p, over
        !! dx^dim (1 inside the body, 1/2 on a face, 1/4 at a corner of a 2D body on the
        !! nodes). The nodes its particles merely reach would drag the material between
        !! them and the body along (a rigid plate on a column: +5 % on its reaction, the
        !! top row of cells never strained; a footing: 20 % wider)

contains

    !> Number of regions of prescribed_motion of a case.
    pure integer function region_count(case)
        type(case_type), intent(in) :: case
            !! the case

        region_count = 0
        if (allocated(case%motions)) region_count = size(case%motions)
    end function region_count

    !> Whether a case has rigid bodies (materials of type "rigid").
    pure logical function has_rigid_bodies(case)
        type(case_type), intent(in) :: case
            !! the case

        has_rigid_bodies = .false.
        if (region_count(case) > 0) has_rigid_bodies = any(case%motions%rigid > 0)
    end function has_rigid_bodies

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

    !> Hold the nodes of every region at time t (the step's start) for the step: the nodes
    !> inside each box region's moved box, and the nodes whose cell each rigid body's particles
    !> fill to a fifth (min_fill, from this step's stencils). A region that would move a component a face
    !> holds (a fixed or sliding face, a velocity face) is an error: the two contradict each
    !> other; so are two regions that reach the same node (a rigid body within a cell of
    !> another, or of a box region: one velocity field cannot move a node two ways).
    subroutine hold_regions(case, grid, t, particles, stc, error)
        type(case_type), intent(in) :: case
            !! the case
        type(grid_type), intent(inout) :: grid
            !! the grid of the step
        real(wp), intent(in) :: t
            !! time of the step's start [s]
        type(particles_type), intent(in) :: particles
            !! the particles (the rigid bodies' nodes)
        type(stencils_type), intent(in) :: stc
            !! their stencils of this step
        type(error_type), allocatable, intent(out) :: error
            !! set when a region contradicts a face or another region

        integer :: r, n, dim, lo(3), hi(3), i, j, k
        real(wp) :: shift(3), factor

        grid%nregion_nodes = 0
        grid%bodies_moved = .false.
        if (region_count(case) == 0) return
        dim = grid%dim
        if (.not. allocated(grid%region_velocity)) then
            allocate (grid%region_velocity(dim, size(case%motions)), &
                grid%region_held(dim, size(case%motions)), &
                grid%region_impulse(dim, size(case%motions)), &
                grid%body_velocity(dim, size(case%motions)), &
                grid%body_start(dim, size(case%motions)), &
                grid%region_rigid(size(case%motions)))
            grid%region_impulse = 0.0_wp
            grid%body_velocity = 0.0_wp
            grid%body_start = 0.0_wp
            grid%region_rigid = case%motions%rigid
        end if
        if (.not. allocated(grid%region_mark)) then
            allocate (grid%region_mark(size(grid%mass)))
            grid%region_mark = 0
        end if
        if (.not. allocated(grid%region_node)) allocate (grid%region_node(64), &
            grid%region_of(64), grid%region_saved(dim, 64))
        n = 0
        do r = 1, size(case%motions)
            associate (motion => case%motions(r))
                factor = motion%time%factor(t)
                grid%region_velocity(:, r) = merge(motion%velocity(1:dim)*factor, 0.0_wp, &
                    motion%held(1:dim))
                grid%region_held(:, r) = motion%held(1:dim)
            end associate
            if (case%motions(r)%rigid > 0) cycle
            call region_box(r, lo, hi)
            do k = lo(3), hi(3)
                do j = lo(2), hi(2)
                    do i = lo(1), hi(1)
                        call add_node(r, 1 + i + grid%nn(1)*(j + grid%nn(2)*k))
                        if (allocated(error)) return
                    end do
                end do
            end do
        end do
        ! the rigid bodies, one after the other: the nodes a fifth of whose cell (at least)
        ! the body fills
        do r = 1, size(case%motions)
            if (case%motions(r)%rigid == 0) cycle
            call body_nodes(r, case%motions(r)%rigid)
            if (allocated(error)) return
        end do
        if (any(case%motions%rigid > 0)) call body_conflicts()
    contains
        !> A rigid body may not touch a velocity face (the lump would stop its nodes instead of
        !> moving them with the face), a frictional face or the terrain (their contacts act on
        !> the nodes one by one, which the lump undoes: the body sank through them).
        subroutine body_conflicts()
            integer :: id
            character(len=:), allocatable :: what
            real(wp) :: x(3)

            what = ""
            id = 0
            if (grid%nprescribed > 0) id = first_body_node(grid%prescribed_node(1:grid%nprescribed))
            if (id > 0) then
                what = "a velocity face"
            else if (grid%ncontacts > 0) then
                id = first_body_node(grid%contact_node(1:grid%ncontacts))
                if (id > 0) what = "a frictional face or the terrain of contact"
            end if
            if (len(what) == 0) return
            x = node_position(id)
            call fatal_error(error, case%file//": at t = "//fmt_real(t, 6)//" s, " &
                //region_text(grid%region_mark(id))//" reaches "//what//" at " &
                //fmt_vector(x(1:dim), 6)//" m, which rigid bodies do not take yet; keep it " &
                //"a cell away (a fixed or sliding face holds a rigid body)", exit_input)
            call release_regions(grid)
        end subroutine body_conflicts

        !> The first of the nodes ids that a rigid body moves in this step, 0 for none.
        integer function first_body_node(ids)
            integer, intent(in) :: ids(:)

            integer :: k

            first_body_node = 0
            do k = 1, size(ids)
                if (grid%region_mark(ids(k)) == 0) cycle
                if (case%motions(grid%region_mark(ids(k)))%rigid == 0) cycle
                first_body_node = ids(k)
                return
            end do
        end function first_body_node

        !> The nodes of rigid body r (material m).
        subroutine body_nodes(r, m)
            integer, intent(in) :: r, m

            integer :: i, j, k, id, p, a(3), d, ntouched, first
            integer, allocatable :: touched(:)
            real(wp) :: weight, mass

            if (.not. allocated(grid%body_fill)) then
                allocate (grid%body_fill(size(grid%mass)))
                grid%body_fill = 0.0_wp
            end if
            allocate (touched(256))
            ntouched = 0
            ! its displacement: the mean of its particles' (all the same but for round-off)
            grid%body_start(:, r) = 0.0_wp
            mass = 0.0_wp
            do p = 1, particles%n
                if (particles%material(p) /= m) cycle
                if (allocated(particles%u)) grid%body_start(:, r) = grid%body_start(:, r) &
                    + particles%mass(p)*particles%u(1:dim, p)
                mass = mass + particles%mass(p)
            end do
            if (mass > 0.0_wp) grid%body_start(:, r) = grid%body_start(:, r)/mass
            do p = 1, particles%n
                if (particles%material(p) /= m) cycle
                do k = 1, stc%nper(3)
                    do j = 1, stc%nper(2)
                        do i = 1, stc%nper(1)
                            a = [i, j, k]
                            if (stc%tensor) then
                                weight = 1.0_wp
                                do d = 1, dim
                                    weight = weight*stc%w(a(d), d, p)
                                end do
                            else
                                weight = stc%wn(i + stc%nper(1)*(j - 1 + stc%nper(2)*(k - 1)), p)
                            end if
                            if (weight <= 0.0_wp) cycle
                            a(1:dim) = stc%first(:, p) + a(1:dim) - 1
                            a(dim + 1:) = 0
                            id = 1 + sum(a*stc%stride)
                            if (grid%body_fill(id) == 0.0_wp) then
                                if (ntouched == size(touched)) touched = [touched, touched]
                                ntouched = ntouched + 1
                                touched(ntouched) = id
                            end if
                            grid%body_fill(id) = grid%body_fill(id) + weight*particles%volume(p)
                        end do
                    end do
                end do
            end do
            first = n
            do i = 1, ntouched
                id = touched(i)
                if (.not. allocated(error) .and. grid%body_fill(id) >= min_fill*grid%dx**dim) then
                    call add_node(r, id)
                end if
                grid%body_fill(id) = 0.0_wp
            end do
            if (allocated(error) .or. ntouched == 0 .or. n > first) return
            call fatal_error(error, case%file//": at t = "//fmt_real(t, 6)//" s, " &
                //region_text(r)//" fills no node's cell to a fifth (it is thinner than a " &
                //"cell): the grid cannot move it as a rigid body; make it thicker or the " &
                //"grid finer (domain.dx)", exit_input)
            call release_regions(grid)
        end subroutine body_nodes

        !> Node id moves with region r: listed, marked, its held components constrained.
        subroutine add_node(r, id)
            integer, intent(in) :: r, id

            integer :: other
            logical, allocatable :: saved(:, :)
            integer, allocatable :: ids(:)

            other = grid%region_mark(id)
            if (other /= 0) then
                call shared_node(other, r, id)
                call release_regions(grid)
                return
            end if
            if (any(grid%constrained(:, id) .and. grid%region_held(:, r) .and. &
                grid%region_velocity(:, r) /= 0.0_wp)) then
                call contradiction(r, id)
                call release_regions(grid)
                return
            end if
            if (n == size(grid%region_node)) then
                ids = grid%region_node
                deallocate (grid%region_node)
                allocate (grid%region_node(2*n))
                grid%region_node(1:n) = ids
                ids = grid%region_of
                deallocate (grid%region_of)
                allocate (grid%region_of(2*n))
                grid%region_of(1:n) = ids
                saved = grid%region_saved
                deallocate (grid%region_saved)
                allocate (grid%region_saved(dim, 2*n))
                grid%region_saved(:, 1:n) = saved
            end if
            n = n + 1
            grid%region_node(n) = id
            grid%region_of(n) = r
            grid%region_saved(:, n) = grid%constrained(:, id)
            grid%region_mark(id) = r
            grid%constrained(:, id) = grid%constrained(:, id) .or. grid%region_held(:, r)
            grid%nregion_nodes = n
        end subroutine add_node

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

        !> The position of node id [m].
        function node_position(id) result(x)
            integer, intent(in) :: id
            real(wp) :: x(3)

            integer :: node(3)

            node = [mod(id - 1, grid%nn(1)), mod((id - 1)/grid%nn(1), grid%nn(2)), &
                (id - 1)/(grid%nn(1)*grid%nn(2))]
            x = grid%origin + grid%dx*real(node, wp)
        end function node_position

        !> The error of two regions that reach node id.
        subroutine shared_node(first, second, id)
            integer, intent(in) :: first, second, id

            real(wp) :: x(3)

            x = node_position(id)
            call fatal_error(error, case%file//": at t = "//fmt_real(t, 6)//" s, " &
                //region_text(first)//" and "//region_text(second)//" reach the same grid " &
                //"node, at "//fmt_vector(x(1:dim), 6)//" m: one velocity " &
                //"field cannot move it two ways. Keep rigid bodies and regions more than a " &
                //"cell apart (dx = "//fmt_real(grid%dx)//" m)", exit_input)
        end subroutine shared_node

        !> "prescribed_motion[r] "name"" or "the rigid body "name"".
        function region_text(r) result(text)
            integer, intent(in) :: r
            character(len=:), allocatable :: text

            if (case%motions(r)%rigid > 0) then
                text = 'the rigid body "'//case%motions(r)%name//'"'
            else
                text = "prescribed_motion["//int_text(r)//'] "'//case%motions(r)%name//'"'
            end if
        end function region_text

        !> The error of a region that moves a held component of a face's node.
        subroutine contradiction(r, id)
            integer, intent(in) :: r, id

            integer :: a, b, node(3)
            real(wp) :: x(3)
            character(len=:), allocatable :: faces

            node = [mod(id - 1, grid%nn(1)), mod((id - 1)/grid%nn(1), grid%nn(2)), &
                (id - 1)/(grid%nn(1)*grid%nn(2))]
            x = node_position(id)
            do a = 1, dim
                if (grid%constrained(a, id) .and. grid%region_held(a, r) .and. &
                    grid%region_velocity(a, r) /= 0.0_wp) exit
            end do
            faces = ""
            do b = 1, dim
                if (node(b) == 0) faces = faces//" "//axis_names(b:b)//"min"
                if (node(b) == grid%nn(b) - 1) faces = faces//" "//axis_names(b:b)//"max"
            end do
            call fatal_error(error, case%file//": "//region_text(r)//" moves the node at " &
                //fmt_vector(x(1:dim), 6)//" m along "//axis_names(a:a)//", which " &
                //"domain.boundaries holds there (face"//faces//"); give the region only " &
                //"the components the face leaves free (components), or keep it off that face", &
                exit_input)
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
            if (noted(r) .or. case%motions(r)%rigid > 0) cycle
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

    !> The displacement of rigid body r: that of its particles (their mean, by mass) [m].
    function body_displacement(case, particles, r) result(d)
        type(case_type), intent(in) :: case
            !! the case
        type(particles_type), intent(in) :: particles
            !! the particles (with their displacements u)
        integer, intent(in) :: r
            !! the region of the body
        real(wp) :: d(3)

        integer :: p, dim
        real(wp) :: mass

        d = 0.0_wp
        mass = 0.0_wp
        dim = case%dim
        if (.not. allocated(particles%u)) return
        do p = 1, particles%n
            if (particles%material(p) /= case%motions(r)%rigid) cycle
            d(1:dim) = d(1:dim) + particles%mass(p)*particles%u(1:dim, p)
            mass = mass + particles%mass(p)
        end do
        if (mass > 0.0_wp) d = d/mass
    end function body_displacement

    !> Give the region nodes back the constraints of their faces (end of the step).
    subroutine release_regions(grid)
        type(grid_type), intent(inout) :: grid
            !! the grid of the step

        integer :: n

        do n = 1, grid%nregion_nodes
            grid%constrained(:, grid%region_node(n)) = grid%region_saved(:, n)
            grid%region_mark(grid%region_node(n)) = 0
        end do
        grid%nregion_nodes = 0
    end subroutine release_regions

end module mpm_motion
