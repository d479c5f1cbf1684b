!> The running normal loads of the contact pairs (frictional faces, terrain), by node of the
!> whole grid.
!>
!> The load of a pair (a running mean of the normal impulse its node took) is the only nodal
!> state one step hands to the next. Keyed by node of the whole grid instead of by pair of
!> an image's grid, the loads follow their nodes when the cuts among the images move
!> (mpm_solver's rebalance) and a checkpoint holds them in a form that does not depend on
!> where the grid was cut. Each node is given by the image that owns it (node_owned); the
!> images of a cut hold the same loads at their shared nodes (their updates see the same
!> nodal sums). Every procedure that gathers is collective.
module mpm_contact_loads
    use mpm_kinds, only: wp, i8
    use mpm_case, only: case_type
    use mpm_boundary, only: face_nodes_type
    use mpm_grid, only: grid_type, node_owned, node_layer
    use mpm_decomposition, only: decomposition_type
    use mpm_parallel, only: sum_over_images, counts_of_images, image_id
    implicit none
    private
    public :: face_loads, take_face_loads, face_node_count, terrain_loads, take_terrain_loads

contains

    !> The running normal loads of the frictional faces, by node of the whole grid's faces
    !> (faces in axis then side order), each node given by the image that owns it.
    !> Collective.
    subroutine face_loads(case, grid, dec, loads)
        type(case_type), intent(in) :: case
            !! resolved case (the whole grid)
        type(grid_type), intent(in) :: grid
            !! this image's grid
        type(decomposition_type), intent(in) :: dec
            !! this image's part of the grid
        real(wp), allocatable, intent(out) :: loads(:)
            !! loads of every frictional face node [N s]

        integer :: c

        allocate (loads(face_node_count(case)))
        loads = 0.0_wp
        do c = 1, grid%ncontacts
            ! (terrain pairs have no face)
            if (grid%contact_axis(c) == 0) cycle
            if (.not. node_owned(grid, grid%contact_node(c))) cycle
            loads(face_node(case, grid, dec, c)) = grid%contact_load(c)
        end do
        call sum_over_images(loads)
    end subroutine face_loads

    !> Set the running normal loads of this image's frictional face nodes from face_loads.
    subroutine take_face_loads(case, grid, dec, loads)
        type(case_type), intent(in) :: case
            !! resolved case (the whole grid)
        type(grid_type), intent(inout) :: grid
            !! this image's grid (a new one)
        type(decomposition_type), intent(in) :: dec
            !! this image's part of the grid
        real(wp), intent(in) :: loads(:)
            !! face_loads of the grid before

        integer :: c

        do c = 1, grid%ncontacts
            if (grid%contact_axis(c) == 0) cycle
            grid%contact_load(c) = loads(face_node(case, grid, dec, c))
        end do
    end subroutine take_face_loads

    !> Number of nodes of the frictional faces of the whole grid.
    pure integer function face_node_count(case)
        type(case_type), intent(in) :: case
            !! resolved case (the whole grid)

        integer :: a, side, nn(3)
        type(face_nodes_type) :: nodes

        nn = 1
        nn(1:case%dim) = case%domain%ncells(1:case%dim) + 1
        face_node_count = 0
        do a = 1, case%dim
            do side = 1, 2
                nodes = case%domain%nodes(side, a, case%dim)
                if (nodes%contact) face_node_count = &
                    face_node_count + product(nn)/nn(a)
            end do
        end do
    end function face_node_count

    !> Index among the whole grid's frictional face nodes (face_loads) of contact pair c of
    !> this image's grid.
    pure integer function face_node(case, grid, dec, c)
        type(case_type), intent(in) :: case
        type(grid_type), intent(in) :: grid
        type(decomposition_type), intent(in) :: dec
        integer, intent(in) :: c
            !! contact pair

        integer :: a, side, b, nn(3), ijk(3), stride, face, s
        type(face_nodes_type) :: nodes

        nn = 1
        nn(1:case%dim) = case%domain%ncells(1:case%dim) + 1
        ijk = global_ijk(grid, dec, grid%contact_node(c))
        a = grid%contact_axis(c)
        side = merge(1, 2, grid%contact_normal(c) < 0.0_wp)
        ! faces before this one
        face_node = 0
        do b = 1, case%dim
            do s = 1, 2
                if (b == a .and. s == side) exit
                nodes = case%domain%nodes(s, b, case%dim)
                if (nodes%contact) face_node = face_node + product(nn)/nn(b)
            end do
            if (b == a) exit
        end do
        face = 1
        stride = 1
        do b = 1, 3
            if (b == a) cycle
            face = face + ijk(b)*stride
            stride = stride*nn(b)
        end do
        face_node = face_node + face
    end function face_node

    !> The running normal loads of the terrain pairs of the whole grid: the node of each
    !> (linear index in the whole grid, ascending) and its load, from the image that owns
    !> it. The same on every image. Collective.
    subroutine terrain_loads(case, grid, dec, node, load)
        type(case_type), intent(in) :: case
            !! resolved case (the whole grid)
        type(grid_type), intent(in) :: grid
            !! this image's grid
        type(decomposition_type), intent(in) :: dec
            !! this image's part of the grid
        integer(i8), allocatable, intent(out) :: node(:)
            !! node of each terrain pair of the whole grid, ascending
        real(wp), allocatable, intent(out) :: load(:)
            !! its running normal load [N s]

        integer(i8), allocatable :: counts(:)
        integer :: c, mine, first, k

        mine = 0
        do c = 1, grid%ncontacts
            if (owned_terrain_pair(c)) mine = mine + 1
        end do
        counts = counts_of_images(mine)
        first = int(sum(counts(1:image_id() - 1)))
        allocate (node(sum(counts)), load(sum(counts)))
        node = 0
        load = 0.0_wp
        k = first
        do c = 1, grid%ncontacts
            if (.not. owned_terrain_pair(c)) cycle
            k = k + 1
            node(k) = global_node(case, grid, dec, grid%contact_node(c))
            load(k) = grid%contact_load(c)
        end do
        call sum_over_images(node)
        call sum_over_images(load)
        ! each image's part is ascending (its pairs are in node order, and a slab's node order
        ! is the whole grid's)
        call merge_parts(counts, node, load)

    contains

        logical function owned_terrain_pair(c)
            integer, intent(in) :: c
            owned_terrain_pair = grid%contact_axis(c) == 0 .and. &
                node_owned(grid, grid%contact_node(c))
        end function owned_terrain_pair

    end subroutine terrain_loads

    !> Set the running normal loads of this image's terrain pairs from terrain_loads (of this
    !> grid before its cuts moved, or of a checkpoint). `complete` is false when a pair's
    !> node is not in the list (a list of another grid or terrain).
    subroutine take_terrain_loads(case, grid, dec, node, load, complete)
        type(case_type), intent(in) :: case
            !! resolved case (the whole grid)
        type(grid_type), intent(inout) :: grid
            !! this image's grid
        type(decomposition_type), intent(in) :: dec
            !! this image's part of the grid
        integer(i8), intent(in) :: node(:)
            !! node of each terrain pair of the whole grid, ascending
        real(wp), intent(in) :: load(:)
            !! its running normal load [N s]
        logical, intent(out) :: complete
            !! every terrain pair of this grid was in the list

        integer :: c, lo, hi, mid
        integer(i8) :: id

        complete = .true.
        do c = 1, grid%ncontacts
            if (grid%contact_axis(c) /= 0) cycle
            id = global_node(case, grid, dec, grid%contact_node(c))
            ! binary search in the ascending list
            lo = 1
            hi = size(node)
            do while (lo < hi)
                mid = lo + (hi - lo)/2
                if (node(mid) < id) then
                    lo = mid + 1
                else
                    hi = mid
                end if
            end do
            if (lo > size(node)) then
                complete = .false.
            else if (node(lo) /= id) then
                complete = .false.
            else
                grid%contact_load(c) = load(lo)
            end if
        end do
    end subroutine take_terrain_loads

    !> Node coordinates (0-based) in the whole grid of node id of this image's grid.
    pure function global_ijk(grid, dec, id) result(ijk)
        type(grid_type), intent(in) :: grid
        type(decomposition_type), intent(in) :: dec
        integer, intent(in) :: id
        integer :: ijk(3)

        integer :: b

        do b = 1, 3
            ijk(b) = node_layer(grid, id, b)
        end do
        if (dec%axis > 0) ijk(dec%axis) = ijk(dec%axis) + dec%node_lo
    end function global_ijk

    !> Linear index (1-based) in the whole grid of node id of this image's grid.
    pure integer(i8) function global_node(case, grid, dec, id)
        type(case_type), intent(in) :: case
        type(grid_type), intent(in) :: grid
        type(decomposition_type), intent(in) :: dec
        integer, intent(in) :: id

        integer :: ijk(3)
        integer(i8) :: nn(3)

        nn = 1
        nn(1:case%dim) = case%domain%ncells(1:case%dim) + 1
        ijk = global_ijk(grid, dec, id)
        global_node = 1_i8 + ijk(1) + nn(1)*(ijk(2) + nn(2)*ijk(3))
    end function global_node

    !> Merge the images' parts of (node, load), each ascending by node, into one ascending
    !> list (part after part: the images are few, the parts long).
    subroutine merge_parts(counts, node, load)
        integer(i8), intent(in) :: counts(:)
            !! length of each image's part, in image order
        integer(i8), intent(inout) :: node(:)
            !! the parts one after the other; on return ascending
        real(wp), intent(inout) :: load(:)
            !! load of each node, reordered with it

        integer(i8), allocatable :: merged_node(:)
        real(wp), allocatable :: merged_load(:)
        integer :: part, done, a, b, k, last

        allocate (merged_node(size(node)), merged_load(size(load)))
        done = int(counts(1))
        do part = 2, size(counts)
            ! node(1:done) is ascending; merge node(done+1:last) into it
            last = done + int(counts(part))
            a = 1
            b = done + 1
            do k = 1, last
                if (b > last) then
                    merged_node(k) = node(a)
                    merged_load(k) = load(a)
                    a = a + 1
                else if (a > done) then
                    merged_node(k) = node(b)
                    merged_load(k) = load(b)
                    b = b + 1
                else if (node(a) <= node(b)) then
                    merged_node(k) = node(a)
                    merged_load(k) = load(a)
                    a = a + 1
                else
                    merged_node(k) = node(b)
                    merged_load(k) = load(b)
                    b = b + 1
                end if
            end do
            node(1:last) = merged_node(1:last)
            load(1:last) = merged_load(1:last)
            done = last
        end do
    end subroutine merge_parts

end module mpm_contact_loads
