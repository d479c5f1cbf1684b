!> The background grid (mpm_grid) on made-up small grids: node counts and zeroed fields,
!> the lexicographic node numbering (node_index, node_layer, node_position) in 2D and 3D,
!> the constraints of sliding and fixed faces, the node-face pairs of a frictional face and
!> their numbering (contact_index), and the bytes per node.
program test_mpm_grid
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, check_close, finish
    use mpm_error, only: error_type
    use mpm_strings, only: int_text
    use mpm_case, only: case_type
    use mpm_boundary_sliding, only: sliding_boundary_type
    use mpm_boundary_fixed, only: fixed_boundary_type
    use mpm_boundary_frictional, only: frictional_boundary_type
    use mpm_grid, only: grid_type, new_grid, node_index, node_layer, node_position, &
        contact_index, grid_bytes
    implicit none

    type(test_suite_type) :: suite

    call new_suite(suite, "mpm_grid")
    call test_counts_2d()
    call test_numbering_2d()
    call test_numbering_3d()
    call test_faces_2d()
    call test_frictional_faces_3d()
    call finish(suite)

contains

    !> A 2D case of 4 x 3 cells of 0.5 m from (1, -1), every face free.
    subroutine small_case_2d(case)
        type(case_type), intent(out) :: case

        case%dim = 2
        case%domain%ncells = [4, 3, 1]
        case%domain%dx = 0.5_wp
        case%domain%origin = [1.0_wp, -1.0_wp, 0.0_wp]
    end subroutine small_case_2d

    !> A 3D case of 2 x 3 x 4 cells of 0.25 m from (0, 1, 2), every face free.
    subroutine small_case_3d(case)
        type(case_type), intent(out) :: case

        case%dim = 3
        case%domain%ncells = [2, 3, 4]
        case%domain%dx = 0.25_wp
        case%domain%origin = [0.0_wp, 1.0_wp, 2.0_wp]
    end subroutine small_case_3d

    subroutine test_counts_2d()
        type(case_type) :: case
        type(grid_type) :: grid
        type(error_type), allocatable :: error

        call small_case_2d(case)
        call new_grid(grid, case, error)
        call check(suite, .not. allocated(error), "new_grid 2D")
        if (allocated(error)) return
        call check(suite, all(grid%nn == [5, 4, 1]), "2D nodes per direction 5 4 1")
        call check(suite, all(grid%ncells == [4, 3, 1]), "2D cells per direction 4 3 1")
        call check(suite, grid%nnodes == 20, "2D node count 20, got "//int_text(grid%nnodes))
        call check(suite, all(shape(grid%momentum) == [2, 20]) .and. &
            all(shape(grid%velocity) == [2, 20]) .and. size(grid%mass) == 20, &
            "2D nodal arrays (dim, nnodes)")
        call check(suite, all(grid%mass == 0.0_wp) .and. all(grid%momentum == 0.0_wp) .and. &
            all(grid%fint == 0.0_wp) .and. all(grid%fext == 0.0_wp) .and. &
            all(grid%velocity == 0.0_wp) .and. all(grid%acceleration == 0.0_wp), &
            "2D nodal fields start at zero")
        call check(suite, .not. any(grid%constrained), "free faces constrain no node")
        call check(suite, grid%ncontacts == 0, "free faces make no contact pair")
        call check(suite, grid_bytes(grid) == 8*(1 + 5*2) + 4*2, &
            "bytes per node: 11 reals and 2 logicals in 2D, got "//int_text(grid_bytes(grid)))
    end subroutine test_counts_2d

    subroutine test_numbering_2d()
        type(case_type) :: case
        type(grid_type) :: grid
        type(error_type), allocatable :: error
        integer :: i, j, id
        logical :: ok_index, ok_layer, ok_position
        real(wp) :: x(3)

        call small_case_2d(case)
        call new_grid(grid, case, error)
        if (allocated(error)) return
        ok_index = .true.
        ok_layer = .true.
        ok_position = .true.
        do j = 0, 3
            do i = 0, 4
                ! x fastest: 1 + i + nn(1) j
                id = node_index(grid, [i, j, 0])
                ok_index = ok_index .and. id == 1 + i + 5*j
                ok_layer = ok_layer .and. node_layer(grid, id, 1) == i .and. &
                    node_layer(grid, id, 2) == j .and. node_layer(grid, id, 3) == 0
                x = node_position(grid, id)
                ok_position = ok_position .and. x(1) == 1.0_wp + 0.5_wp*i .and. &
                    x(2) == -1.0_wp + 0.5_wp*j .and. x(3) == 0.0_wp
            end do
        end do
        call check(suite, ok_index, "2D node_index is 1 + i + nn(1) j")
        call check(suite, ok_layer, "2D node_layer inverts node_index")
        call check(suite, ok_position, "2D node_position is origin + dx (i, j) (exact)")
        x = node_position(grid, grid%nnodes)
        call check_close(suite, x(1), 3.0_wp, 0.0_wp, "last node x = 1 + 4 x 0.5")
        call check_close(suite, x(2), 0.5_wp, 0.0_wp, "last node y = -1 + 3 x 0.5")
    end subroutine test_numbering_2d

    subroutine test_numbering_3d()
        type(case_type) :: case
        type(grid_type) :: grid
        type(error_type), allocatable :: error
        integer :: i, j, k, id
        logical :: ok_index, ok_layer, ok_position
        logical, allocatable :: seen(:)
        real(wp) :: x(3)

        call small_case_3d(case)
        call new_grid(grid, case, error)
        call check(suite, .not. allocated(error), "new_grid 3D")
        if (allocated(error)) return
        call check(suite, all(grid%nn == [3, 4, 5]) .and. grid%nnodes == 60, &
            "3D nodes 3 x 4 x 5 = 60, got "//int_text(grid%nnodes))
        allocate (seen(grid%nnodes))
        seen = .false.
        ok_index = .true.
        ok_layer = .true.
        ok_position = .true.
        do k = 0, 4
            do j = 0, 3
                do i = 0, 2
                    id = node_index(grid, [i, j, k])
                    ok_index = ok_index .and. id == 1 + i + 3*(j + 4*k)
                    if (id >= 1 .and. id <= grid%nnodes) seen(id) = .true.
                    ok_layer = ok_layer .and. node_layer(grid, id, 1) == i .and. &
                        node_layer(grid, id, 2) == j .and. node_layer(grid, id, 3) == k
                    x = node_position(grid, id)
                    ok_position = ok_position .and. &
                        all(x == [0.25_wp*i, 1.0_wp + 0.25_wp*j, 2.0_wp + 0.25_wp*k])
                end do
            end do
        end do
        call check(suite, ok_index, "3D node_index is 1 + i + nn(1) (j + nn(2) k)")
        call check(suite, all(seen), "3D node_index numbers every node once")
        call check(suite, ok_layer, "3D node_layer inverts node_index")
        call check(suite, ok_position, "3D node_position is origin + dx (i, j, k) (exact)")
    end subroutine test_numbering_3d

    !> x min fixed, x max sliding, y min frictional (mu 0.3), y max free.
    subroutine test_faces_2d()
        type(case_type) :: case
        type(grid_type) :: grid
        type(error_type), allocatable :: error
        integer :: i, j, id, c
        logical :: ok_fixed, ok_sliding, ok_inner, ok_pairs, ok_index

        call small_case_2d(case)
        allocate (fixed_boundary_type :: case%domain%face(1, 1)%b)
        allocate (sliding_boundary_type :: case%domain%face(2, 1)%b)
        allocate (case%domain%face(1, 2)%b, source=frictional_boundary_type(mu=0.3_wp))
        call new_grid(grid, case, error)
        call check(suite, .not. allocated(error), "new_grid 2D with faces")
        if (allocated(error)) return
        ok_fixed = .true.
        ok_sliding = .true.
        ok_inner = .true.
        do j = 0, 3
            do i = 0, 4
                id = node_index(grid, [i, j, 0])
                if (i == 0) then
                    ok_fixed = ok_fixed .and. all(grid%constrained(:, id))
                else if (i == 4) then
                    ! normal component only
                    ok_sliding = ok_sliding .and. grid%constrained(1, id) .and. &
                        .not. grid%constrained(2, id)
                else
                    ! the frictional and the free face constrain nothing
                    ok_inner = ok_inner .and. .not. any(grid%constrained(:, id))
                end if
            end do
        end do
        call check(suite, ok_fixed, "fixed face: every component of its nodes held")
        call check(suite, ok_sliding, "sliding face: the normal component only")
        call check(suite, ok_inner, "other nodes (frictional, free faces, inside) unconstrained")

        call check(suite, grid%ncontacts == 5, "a frictional face of 5 nodes makes 5 pairs, got "// &
            int_text(grid%ncontacts))
        if (grid%ncontacts /= 5) return
        ok_pairs = .true.
        do c = 1, 5
            ok_pairs = ok_pairs .and. grid%contact_node(c) == node_index(grid, [c - 1, 0, 0]) .and. &
                grid%contact_axis(c) == 2 .and. grid%contact_normal(c) == -1.0_wp .and. &
                all(grid%contact_dir(:, c) == [0.0_wp, -1.0_wp]) .and. &
                grid%contact_mu(c) == 0.3_wp .and. grid%contact_load(c) == 0.0_wp .and. &
                grid%contact_gap(c) == huge(1.0_wp)
        end do
        call check(suite, ok_pairs, "pairs of y min: its nodes in x order, axis 2, normal -y, "// &
            "mu 0.3, no load, no gap")
        ok_index = .true.
        do id = 1, grid%nnodes
            if (node_layer(grid, id, 2) == 0) then
                ok_index = ok_index .and. contact_index(grid, id, 1, 2) == node_layer(grid, id, 1) + 1
            else
                ok_index = ok_index .and. contact_index(grid, id, 1, 2) == 0
            end if
            ! faces that are not frictional have no pairs
            ok_index = ok_index .and. contact_index(grid, id, 2, 2) == 0 .and. &
                contact_index(grid, id, 1, 1) == 0 .and. contact_index(grid, id, 2, 1) == 0
        end do
        call check(suite, ok_index, "contact_index: the pair of a node of y min, 0 elsewhere")
    end subroutine test_faces_2d

    !> Two frictional faces in 3D (z min, x max): the pairs of each face in a block of their
    !> own, numbered like the face's nodes (lowest remaining axis fastest).
    subroutine test_frictional_faces_3d()
        type(case_type) :: case
        type(grid_type) :: grid
        type(error_type), allocatable :: error
        integer :: id, c, expected, i, j, k
        logical :: ok

        call small_case_3d(case)
        allocate (case%domain%face(1, 3)%b, source=frictional_boundary_type(mu=0.5_wp))
        allocate (case%domain%face(2, 1)%b, source=frictional_boundary_type(mu=0.1_wp))
        call new_grid(grid, case, error)
        if (allocated(error)) return
        ! x max: 4 x 5 nodes; z min: 3 x 4 nodes
        call check(suite, grid%ncontacts == 20 + 12, "3D: 20 + 12 pairs, got "// &
            int_text(grid%ncontacts))
        if (grid%ncontacts /= 32) return
        ok = .true.
        do id = 1, grid%nnodes
            i = node_layer(grid, id, 1)
            j = node_layer(grid, id, 2)
            k = node_layer(grid, id, 3)
            ! the faces are taken axis by axis: x max first, then z min
            expected = 0
            if (i == 2) expected = 1 + j + 4*k
            ok = ok .and. contact_index(grid, id, 2, 1) == expected
            if (expected > 0) ok = ok .and. grid%contact_node(expected) == id .and. &
                grid%contact_mu(expected) == 0.1_wp .and. &
                all(grid%contact_dir(:, expected) == [1.0_wp, 0.0_wp, 0.0_wp])
            expected = 0
            if (k == 0) expected = 20 + 1 + i + 3*j
            ok = ok .and. contact_index(grid, id, 1, 3) == expected
            if (expected > 0) ok = ok .and. grid%contact_node(expected) == id .and. &
                grid%contact_mu(expected) == 0.5_wp .and. &
                all(grid%contact_dir(:, expected) == [0.0_wp, 0.0_wp, -1.0_wp])
        end do
        call check(suite, ok, "3D pairs: x max then z min, each numbered like its nodes")
        c = count(grid%constrained)
        call check(suite, c == 0, "frictional faces constrain no component, got "//int_text(c))
    end subroutine test_frictional_faces_3d

end program test_mpm_grid
