!> Halo exchange: the nodal sums of the node layers two images share.
!>
!> Where the grid is cut among images (mpm_decomposition), the node layers around a cut
!> (`layers` of them: the halo width of the shape function, shape_type%halo_width; three
!> for linear and cpGIMP) are on both images, and each holds the sums of its own particles
!> only. After each
!> scatter the images trade those layers and add the neighbour's part, so both hold the
!> whole sum (a + b on one and b + a on the other: the same bits) and their nodal updates
!> agree. Before the first scatter of a step the images also trade the part of their box of
!> touched nodes that lies in the shared layers (halo_box): each image's box then holds every
!> shared node that a particle of either image touches, so both images hold the same values
!> at each shared node, also one that only the neighbour's particles touch (the running
!> contact loads of such a node, and the energy sums of the image that owns it, need them).
!> Nodes outside the box take nothing and stay zero (mpm_transfer's fold).
!>
!> The light nodes (mpm_kernel_light) are found, folded and slaved here: the kernel does this
!> image's part, and on a cut grid this module trades the shared layers.
module mpm_halo
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type, node_layer
    use mpm_parallel, only: exchange_neighbours
    use mpm_kernel_light, only: find_light_nodes, fold_light_local, fold_light_mass_local, &
        slave_light_local, light_increments, light_slaved_values
    implicit none
    private
    public :: halo_sum, halo_contact_gaps, halo_box, halo_nodes, halo_pairs, box_part, grow_box
    public :: settle_light_nodes, fold_light, slave_light

contains

    !> Add the neighbours' parts of the shared nodes' mass, momentum and forces (the fields
    !> the last scatter wrote; a field not named is not traded).
    subroutine halo_sum(grid, layers, mass, momentum, fint, fext)
        type(grid_type), intent(inout) :: grid
            !! grid after a scatter (fold)
        integer, intent(in) :: layers
            !! node layers shared at a cut (shape_type%halo_width)
        logical, intent(in), optional :: mass
            !! mass was scattered
        logical, intent(in), optional :: momentum
            !! momentum was scattered
        logical, intent(in), optional :: fint
            !! internal force was scattered
        logical, intent(in), optional :: fext
            !! extra body force was scattered

        integer, allocatable :: lo_nodes(:), hi_nodes(:)
        real(wp), allocatable :: send_lo(:), send_hi(:), recv_lo(:), recv_hi(:)
        logical :: with_mass, with_momentum, with_fint, with_fext

        if (grid%halo_axis == 0) return
        with_mass = .false.
        if (present(mass)) with_mass = mass
        with_momentum = .false.
        if (present(momentum)) with_momentum = momentum
        with_fint = .false.
        if (present(fint)) with_fint = fint
        with_fext = .false.
        if (present(fext)) with_fext = fext
        call halo_nodes(grid, layers, lo_nodes, hi_nodes)
        call pack_side(lo_nodes, send_lo)
        call pack_side(hi_nodes, send_hi)
        call exchange_neighbours(grid%halo_left, grid%halo_right, send_lo, send_hi, recv_lo, &
            recv_hi)
        call add_side(lo_nodes, recv_lo)
        call add_side(hi_nodes, recv_hi)

    contains

        subroutine pack_side(nodes, buf)
            integer, intent(in) :: nodes(:)
            real(wp), allocatable, intent(out) :: buf(:)

            integer :: k, r, id, d

            d = grid%dim
            allocate (buf(size(nodes)*rows()))
            r = 0
            do k = 1, size(nodes)
                id = nodes(k)
                if (with_mass) then
                    buf(r + 1) = grid%mass(id)
                    r = r + 1
                end if
                if (with_momentum) then
                    buf(r + 1:r + d) = grid%momentum(:, id)
                    r = r + d
                end if
                if (with_fint) then
                    buf(r + 1:r + d) = grid%fint(:, id)
                    r = r + d
                end if
                if (with_fext) then
                    buf(r + 1:r + d) = grid%fext(:, id)
                    r = r + d
                end if
            end do
        end subroutine pack_side

        subroutine add_side(nodes, buf)
            integer, intent(in) :: nodes(:)
            real(wp), intent(in) :: buf(:)

            integer :: k, r, id, d

            if (size(buf) == 0) return
            d = grid%dim
            r = 0
            do k = 1, size(nodes)
                id = nodes(k)
                if (.not. in_box(grid, id)) then
                    r = r + rows()
                    cycle
                end if
                if (with_mass) then
                    grid%mass(id) = grid%mass(id) + buf(r + 1)
                    r = r + 1
                end if
                if (with_momentum) then
                    grid%momentum(:, id) = grid%momentum(:, id) + buf(r + 1:r + d)
                    r = r + d
                end if
                if (with_fint) then
                    grid%fint(:, id) = grid%fint(:, id) + buf(r + 1:r + d)
                    r = r + d
                end if
                if (with_fext) then
                    grid%fext(:, id) = grid%fext(:, id) + buf(r + 1:r + d)
                    r = r + d
                end if
            end do
        end subroutine add_side

        integer function rows()
            rows = 0
            if (with_mass) rows = rows + 1
            if (with_momentum) rows = rows + grid%dim
            if (with_fint) rows = rows + grid%dim
            if (with_fext) rows = rows + grid%dim
        end function rows

    end subroutine halo_sum

    !> Grow this image's box of touched nodes (0-based node coordinates, lo > hi along an axis
    !> when empty) by the shared nodes its neighbours' particles touch. Collective.
    subroutine halo_box(grid, layers, lo, hi)
        type(grid_type), intent(in) :: grid
            !! this image's grid
        integer, intent(in) :: layers
            !! node layers shared at a cut (shape_type%halo_width)
        integer, intent(inout) :: lo(3), hi(3)
            !! box of the nodes this image's particles touch; on return the box that also
            !! holds the shared nodes the neighbours' particles touch

        integer :: n, a
        real(wp), allocatable :: send_lo(:), send_hi(:), recv_lo(:), recv_hi(:)

        if (grid%halo_axis == 0) return
        a = grid%halo_axis
        n = grid%nn(a)
        ! the part of the box in each side's shared layers, counted from the side's first
        ! shared layer along the cut axis (the neighbour's numbering of the same layers)
        if (grid%halo_left > 0) then
            send_lo = real(box_part(lo, hi, a, 0, layers - 1), wp)
        else
            allocate (send_lo(0))
        end if
        if (grid%halo_right > 0) then
            send_hi = real(box_part(lo, hi, a, n - layers, n - 1), wp)
        else
            allocate (send_hi(0))
        end if
        call exchange_neighbours(grid%halo_left, grid%halo_right, send_lo, send_hi, recv_lo, &
            recv_hi, most=6)
        if (size(recv_lo) == 6) call grow_box(lo, hi, nint(recv_lo), a, 0, grid%dim)
        if (size(recv_hi) == 6) call grow_box(lo, hi, nint(recv_hi), a, n - layers, grid%dim)
    end subroutine halo_box

    !> The part of the box lo .. hi (0-based node coordinates) in the node layers l0 .. l1 of
    !> axis a, its coordinates along a counted from l0: [lo, hi] of the part (lo > hi along
    !> a when the box misses those layers).
    pure function box_part(lo, hi, a, l0, l1) result(part)
        integer, intent(in) :: lo(3), hi(3)
            !! the box
        integer, intent(in) :: a
            !! axis of the layers
        integer, intent(in) :: l0, l1
            !! first and last layer
        integer :: part(6)
            !! lower then upper corner of the part

        part(1:3) = lo
        part(4:6) = hi
        part(a) = max(lo(a), l0) - l0
        part(3 + a) = min(hi(a), l1) - l0
    end function box_part

    !> Grow the box lo .. hi by the part of a neighbour's box that box_part gave (its
    !> coordinates along axis a counted from this image's layer `first`); an empty part leaves
    !> the box, an empty box becomes the part.
    pure subroutine grow_box(lo, hi, part, a, first, dim)
        integer, intent(inout) :: lo(3), hi(3)
            !! the box (0-based node coordinates; lo > hi along an axis when empty)
        integer, intent(in) :: part(6)
            !! lower then upper corner of the neighbour's part
        integer, intent(in) :: a
            !! axis of the cut
        integer, intent(in) :: first
            !! this image's layer of the part's layer 0
        integer, intent(in) :: dim
            !! space dimensions

        integer :: rlo(3), rhi(3)

        rlo = part(1:3)
        rhi = part(4:6)
        rlo(a) = rlo(a) + first
        rhi(a) = rhi(a) + first
        if (any(rhi(1:dim) < rlo(1:dim))) return
        if (any(hi(1:dim) < lo(1:dim))) then
            lo = rlo
            hi = rhi
        else
            lo = min(lo, rlo)
            hi = max(hi, rhi)
        end if
    end subroutine grow_box

    !> The gap between the material and a frictional face at a shared node is the smaller of
    !> the two images' gaps (P2G sets it from the particles of this image).
    subroutine halo_contact_gaps(grid, layers)
        type(grid_type), intent(inout) :: grid
            !! grid after P2G
        integer, intent(in) :: layers
            !! node layers shared at a cut (shape_type%halo_width)

        integer, allocatable :: lo_pairs(:), hi_pairs(:)
        real(wp), allocatable :: send_lo(:), send_hi(:), recv_lo(:), recv_hi(:)
        integer :: k

        if (grid%halo_axis == 0 .or. grid%ncontacts == 0) return
        call halo_pairs(grid, layers, lo_pairs, hi_pairs)
        send_lo = grid%contact_gap(lo_pairs)
        send_hi = grid%contact_gap(hi_pairs)
        call exchange_neighbours(grid%halo_left, grid%halo_right, send_lo, send_hi, recv_lo, &
            recv_hi)
        do k = 1, size(recv_lo)
            grid%contact_gap(lo_pairs(k)) = min(grid%contact_gap(lo_pairs(k)), recv_lo(k))
        end do
        do k = 1, size(recv_hi)
            grid%contact_gap(hi_pairs(k)) = min(grid%contact_gap(hi_pairs(k)), recv_hi(k))
        end do
    end subroutine halo_contact_gaps

    !> The shared nodes at the low and high ends of halo_axis (none without a neighbour
    !> there), in lexicographic order: the neighbour lists the same nodes in the same order.
    subroutine halo_nodes(grid, layers, lo_nodes, hi_nodes)
        type(grid_type), intent(in) :: grid
            !! this image's grid (halo_axis set)
        integer, intent(in) :: layers
            !! node layers shared at a cut (shape_type%halo_width)
        integer, allocatable, intent(out) :: lo_nodes(:), hi_nodes(:)
            !! shared node indices at the low and the high end

        integer :: n

        n = grid%nn(grid%halo_axis)
        if (grid%halo_left > 0) then
            lo_nodes = layer_nodes(grid, 0, layers - 1)
        else
            allocate (lo_nodes(0))
        end if
        if (grid%halo_right > 0) then
            hi_nodes = layer_nodes(grid, n - layers, n - 1)
        else
            allocate (hi_nodes(0))
        end if
    end subroutine halo_nodes

    !> Nodes whose index along halo_axis is in [l0, l1], in lexicographic order.
    function layer_nodes(grid, l0, l1) result(nodes)
        type(grid_type), intent(in) :: grid
        integer, intent(in) :: l0, l1
        integer, allocatable :: nodes(:)

        integer :: lo(3), hi(3), i, j, k, m

        lo = 0
        hi = grid%nn - 1
        lo(grid%halo_axis) = l0
        hi(grid%halo_axis) = l1
        allocate (nodes(product(hi - lo + 1)))
        m = 0
        do k = lo(3), hi(3)
            do j = lo(2), hi(2)
                do i = lo(1), hi(1)
                    m = m + 1
                    nodes(m) = 1 + i + grid%nn(1)*(j + grid%nn(2)*k)
                end do
            end do
        end do
    end function layer_nodes

    !> Frictional contact pairs at the shared nodes of each end, in pair order (faces in a
    !> fixed order, nodes of a face in lexicographic order: the neighbour's order too).
    subroutine halo_pairs(grid, layers, lo_pairs, hi_pairs)
        type(grid_type), intent(in) :: grid
            !! this image's grid (halo_axis set) with its contact pairs
        integer, intent(in) :: layers
            !! node layers shared at a cut (shape_type%halo_width)
        integer, allocatable, intent(out) :: lo_pairs(:), hi_pairs(:)
            !! contact pairs at shared nodes of the low and the high end

        integer :: c, layer, n
        logical :: lo_side(grid%ncontacts), hi_side(grid%ncontacts)

        n = grid%nn(grid%halo_axis)
        do c = 1, grid%ncontacts
            layer = node_layer(grid, grid%contact_node(c), grid%halo_axis)
            lo_side(c) = grid%halo_left > 0 .and. layer < layers
            hi_side(c) = grid%halo_right > 0 .and. layer >= n - layers
        end do
        lo_pairs = pack([(c, c = 1, grid%ncontacts)], lo_side)
        hi_pairs = pack([(c, c = 1, grid%ncontacts)], hi_side)
    end subroutine halo_pairs

    !> Whether node id is in the box of nodes the last scatter of this image touched.
    pure logical function in_box(grid, id)
        type(grid_type), intent(in) :: grid
        integer, intent(in) :: id

        integer :: a, layer

        in_box = .true.
        do a = 1, grid%dim
            layer = node_layer(grid, id, a)
            in_box = in_box .and. layer >= grid%active_lo(a) .and. layer <= grid%active_hi(a)
        end do
    end function in_box

    !> The light nodes of the step and their masters, from the masses of P2G (summed over the
    !> images); folds the mass and momentum of each into its masters (the light node keeps
    !> none). Collective on a cut grid.
    subroutine settle_light_nodes(grid, layers)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set by P2G (and summed over the images)
        integer, intent(in) :: layers
            !! node layers shared at a cut (shape_type%halo_width)

        real(wp), allocatable :: mass(:, :)

        call find_light_nodes(grid, layers)
        if (grid%light_mass <= 0.0_wp) return
        ! the masses first: the coefficients are those of the masses of P2G
        if (grid%halo_axis /= 0) then
            mass = reshape(grid%mass, [1, size(grid%mass)])
            call fold_cut(grid, mass, held=.false.)
            grid%mass = mass(1, :)
        else
            call fold_light_mass_local(grid)
        end if
        call fold_light(grid, grid%momentum)
    end subroutine settle_light_nodes

    !> Give the nodal field (dim, nnodes) of each light node to its masters, f_j += c_j f_l,
    !> and zero it there (a second call adds nothing); held components are the support's.
    !> Collective on a cut grid.
    subroutine fold_light(grid, field)
        type(grid_type), intent(in) :: grid
            !! the grid with its light nodes found
        real(wp), intent(inout) :: field(:, :)
            !! momentum or force

        if (grid%light_mass <= 0.0_wp) return
        if (grid%halo_axis /= 0) then
            call fold_cut(grid, field, held=.true.)
        else
            call fold_light_local(grid, field)
        end if
    end subroutine fold_light

    !> The nodal field (dim, nnodes) of each light node from its masters, f_l = sum_j c_j f_j
    !> (held components zero); on a cut grid the image that treats a shared light node gives
    !> its values to the other. Collective on a cut grid.
    subroutine slave_light(grid, field)
        type(grid_type), intent(in) :: grid
            !! the grid with its light nodes found
        real(wp), intent(inout) :: field(:, :)
            !! velocity or acceleration

        if (grid%light_mass <= 0.0_wp) return
        call slave_light_local(grid, field)
        if (grid%halo_axis /= 0) call trade_slaved(grid, field)
    end subroutine slave_light

    !> fold_light on a cut grid: the folds of this image's light nodes as increments, traded
    !> over the shared layers and added in image order (the left neighbour's, this image's,
    !> the right neighbour's), so both images of a shared node add the same numbers in the
    !> same order. Collective.
    subroutine fold_cut(grid, field, held)
        type(grid_type), intent(in) :: grid
            !! the cut grid with this image's light nodes found
        real(wp), intent(inout) :: field(:, :)
            !! mass (1, nnodes), momentum or force (dim, nnodes)
        logical, intent(in) :: held
            !! the rows are the grid's components: held components of a light node give
            !! nothing

        real(wp), allocatable :: delta(:, :), send_lo(:), send_hi(:), recv_lo(:), recv_hi(:)
        integer, allocatable :: lo_nodes(:), hi_nodes(:)
        integer :: r

        r = size(field, 1)
        allocate (delta(r, size(field, 2)))
        call light_increments(grid, field, held, delta)
        call halo_nodes(grid, grid%light_layers, lo_nodes, hi_nodes)
        send_lo = reshape(delta(:, lo_nodes), [r*size(lo_nodes)])
        send_hi = reshape(delta(:, hi_nodes), [r*size(hi_nodes)])
        call exchange_neighbours(grid%halo_left, grid%halo_right, send_lo, send_hi, recv_lo, &
            recv_hi)
        if (size(recv_lo) > 0) field(:, lo_nodes) = field(:, lo_nodes) &
            + reshape(recv_lo, [r, size(lo_nodes)])
        field = field + delta
        if (size(recv_hi) > 0) field(:, hi_nodes) = field(:, hi_nodes) &
            + reshape(recv_hi, [r, size(hi_nodes)])
    end subroutine fold_cut

    !> The slaved values of the light nodes in the shared layers from the image that treats
    !> them (a flag and the values per shared node). Collective.
    subroutine trade_slaved(grid, field)
        type(grid_type), intent(in) :: grid
            !! the cut grid with this image's light nodes found
        real(wp), intent(inout) :: field(:, :)
            !! velocity or acceleration (dim, nnodes)

        real(wp), allocatable :: mine(:, :), send_lo(:), send_hi(:), recv_lo(:), recv_hi(:)
        integer, allocatable :: lo_nodes(:), hi_nodes(:)
        integer :: r

        r = size(field, 1)
        allocate (mine(r + 1, size(field, 2)))
        call light_slaved_values(grid, field, mine)
        call halo_nodes(grid, grid%light_layers, lo_nodes, hi_nodes)
        send_lo = reshape(mine(:, lo_nodes), [(r + 1)*size(lo_nodes)])
        send_hi = reshape(mine(:, hi_nodes), [(r + 1)*size(hi_nodes)])
        call exchange_neighbours(grid%halo_left, grid%halo_right, send_lo, send_hi, recv_lo, &
            recv_hi)
        call take(lo_nodes, recv_lo)
        call take(hi_nodes, recv_hi)

    contains

        subroutine take(nodes, buf)
            integer, intent(in) :: nodes(:)
            real(wp), intent(in) :: buf(:)

            integer :: m, b

            if (size(buf) == 0) return
            do m = 1, size(nodes)
                b = (m - 1)*(r + 1)
                if (buf(b + 1) > 0.5_wp) field(:, nodes(m)) = buf(b + 2:b + r + 1)
            end do
        end subroutine take

    end subroutine trade_slaved

end module mpm_halo
