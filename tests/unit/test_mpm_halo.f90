!> The halo of a cut grid (mpm_halo) on made-up grids, without other images: the shared
!> nodes of each end are the `layers` node layers there (none without a neighbour), in
!> lexicographic order so that both images list them alike; the contact pairs at those nodes;
!> the part of a box in the shared layers, counted from the side's first layer, and the box
!> grown by a neighbour's part; and a halo sum or box exchange on one image changes nothing.
program test_mpm_halo
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_grid, only: grid_type, node_layer
    use mpm_halo, only: halo_nodes, halo_pairs, box_part, grow_box, halo_sum, halo_box
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_halo")
    call check_nodes(2, 1, 3)
    call check_nodes(2, 2, 3)
    call check_nodes(3, 3, 3)
    call check_nodes(3, 1, 5)
    call check_pairs()
    call check_box()
    call check_one_image()
    call finish(suite)

contains

    !> A grid of 9 x 7 (x 6) nodes cut along `axis`, neighbours on both sides.
    subroutine make_grid(grid, dim, axis)
        type(grid_type), intent(out) :: grid
        integer, intent(in) :: dim, axis

        integer, parameter :: nodes(3) = [9, 7, 6]

        grid%dim = dim
        grid%nn = 1
        grid%nn(1:dim) = nodes(1:dim)
        grid%ncells = max(1, grid%nn - 1)
        grid%nnodes = product(grid%nn)
        grid%dx = 0.5_wp
        grid%origin = 0.0_wp
        grid%halo_axis = axis
        grid%halo_left = 1
        grid%halo_right = 3
    end subroutine make_grid

    !> The shared nodes of each end of a grid cut along `axis`, `layers` deep.
    subroutine check_nodes(dim, axis, layers)
        integer, intent(in) :: dim, axis, layers

        type(grid_type) :: grid
        integer, allocatable :: lo_nodes(:), hi_nodes(:), expect_lo(:), expect_hi(:)
        integer :: id, n, across
        character(len=40) :: what

        write (what, "(i1,a,i1,a,i1,a)") dim, "D, cut along ", axis, ", ", layers, " layers: "
        call make_grid(grid, dim, axis)
        n = grid%nn(axis)
        across = grid%nnodes/n
        call halo_nodes(grid, layers, lo_nodes, hi_nodes)
        ! every node of the grid in index order, kept when in the end layers
        expect_lo = pack([(id, id = 1, grid%nnodes)], &
            [(node_layer(grid, id, axis) < layers, id = 1, grid%nnodes)])
        expect_hi = pack([(id, id = 1, grid%nnodes)], &
            [(node_layer(grid, id, axis) >= n - layers, id = 1, grid%nnodes)])
        call check(suite, size(lo_nodes) == layers*across .and. size(hi_nodes) == layers*across, &
            trim(what)//"layers x nodes across at each end")
        call check(suite, same(lo_nodes, expect_lo), trim(what)//"low end: its layers, in order")
        call check(suite, same(hi_nodes, expect_hi), trim(what)//"high end: its layers, in order")
        grid%halo_left = 0
        call halo_nodes(grid, layers, lo_nodes, hi_nodes)
        call check(suite, size(lo_nodes) == 0 .and. same(hi_nodes, expect_hi), &
            trim(what)//"no neighbour below: nothing shared there")
        grid%halo_left = 1
        grid%halo_right = 0
        call halo_nodes(grid, layers, lo_nodes, hi_nodes)
        call check(suite, size(hi_nodes) == 0 .and. same(lo_nodes, expect_lo), &
            trim(what)//"no neighbour above: nothing shared there")
    end subroutine check_nodes

    !> Contact pairs at the shared nodes: those whose node is in an end's layers.
    subroutine check_pairs()
        type(grid_type) :: grid
        integer, allocatable :: lo_pairs(:), hi_pairs(:)

        call make_grid(grid, 2, 1)
        ! pairs on nodes of x layers 0, 2, 3, 8, 6, 5 (row y = 0 and 1)
        grid%ncontacts = 6
        grid%contact_node = [1, 3 + 9, 4, 9, 7 + 9, 6]
        call halo_pairs(grid, 3, lo_pairs, hi_pairs)
        call check(suite, same(lo_pairs, [1, 2]), "pairs at the low end's 3 layers")
        call check(suite, same(hi_pairs, [4, 5]), "pairs at the high end's 3 layers")
        call halo_pairs(grid, 4, lo_pairs, hi_pairs)
        call check(suite, same(lo_pairs, [1, 2, 3]) .and. same(hi_pairs, [4, 5, 6]), &
            "pairs at 4 layers")
        grid%halo_right = 0
        call halo_pairs(grid, 3, lo_pairs, hi_pairs)
        call check(suite, same(lo_pairs, [1, 2]) .and. size(hi_pairs) == 0, &
            "no pairs shared without a neighbour")
    end subroutine check_pairs

    !> The part of a box in the shared layers and the box grown by a neighbour's part.
    subroutine check_box()
        integer :: lo(3), hi(3)

        ! box x 2..8, y 1..4 on a grid of 10 nodes along x, 3 shared layers
        call check(suite, same(box_part([2, 1, 0], [8, 4, 0], 1, 0, 2), [2, 1, 0, 2, 4, 0]), &
            "part of a box in the low layers")
        call check(suite, same(box_part([2, 1, 0], [8, 4, 0], 1, 7, 9), [0, 1, 0, 1, 4, 0]), &
            "part of a box in the high layers, from the first of them")
        call check(suite, same(box_part([5, 1, 0], [6, 4, 0], 1, 0, 2), [5, 1, 0, 2, 4, 0]), &
            "a box that misses the layers gives an empty part")
        call check(suite, same(box_part([0, 0, 1], [3, 3, 5], 3, 3, 5), [0, 0, 0, 3, 3, 2]), &
            "part along z")
        ! a neighbour's part of its low layers 0..1 (this image's 7..8) grows the box
        lo = [2, 1, 0]
        hi = [5, 4, 0]
        call grow_box(lo, hi, [0, 0, 0, 1, 6, 0], 1, 7, 2)
        call check(suite, same(lo, [2, 0, 0]) .and. same(hi, [8, 6, 0]), &
            "box grown by the neighbour's part")
        call grow_box(lo, hi, [5, 1, 0, 2, 4, 0], 1, 0, 2)
        call check(suite, same(lo, [2, 0, 0]) .and. same(hi, [8, 6, 0]), &
            "an empty part leaves the box")
        lo = [0, 0, 0]
        hi = [-1, -1, 0]
        call grow_box(lo, hi, [1, 2, 0, 2, 3, 0], 1, 0, 2)
        call check(suite, same(lo, [1, 2, 0]) .and. same(hi, [2, 3, 0]), &
            "an empty box becomes the part")
    end subroutine check_box

    !> On one image the exchanges bring nothing: a halo sum and a box exchange change nothing
    !> (the serial build runs them with a cut grid only here).
    subroutine check_one_image()
        type(grid_type) :: grid
        integer :: lo(3), hi(3), id
        real(wp), allocatable :: mass(:)

        call make_grid(grid, 2, 1)
        allocate (grid%mass(grid%nnodes), grid%momentum(2, grid%nnodes), &
            grid%fint(2, grid%nnodes), grid%fext(2, grid%nnodes))
        grid%mass = [(real(id, wp), id = 1, grid%nnodes)]
        grid%momentum = 1.0_wp
        grid%fint = 2.0_wp
        grid%fext = 3.0_wp
        mass = grid%mass
        call halo_sum(grid, 3, mass=.true., momentum=.true., fint=.true., fext=.true.)
        call check(suite, all(grid%mass == mass) .and. all(grid%momentum == 1.0_wp) .and. &
            all(grid%fint == 2.0_wp) .and. all(grid%fext == 3.0_wp), &
            "one image: the halo sum changes nothing")
        lo = [2, 1, 0]
        hi = [5, 4, 0]
        call halo_box(grid, 3, lo, hi)
        call check(suite, same(lo, [2, 1, 0]) .and. same(hi, [5, 4, 0]), &
            "one image: the box exchange changes nothing")
    end subroutine check_one_image

    pure logical function same(a, b)
        integer, intent(in) :: a(:), b(:)
        same = size(a) == size(b)
        if (same) same = all(a == b)
    end function same

end program test_mpm_halo
