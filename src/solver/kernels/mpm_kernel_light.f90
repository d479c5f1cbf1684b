!> Light nodes, slaved to their heavy neighbours.
!>
!> A node whose mass after P2G is at most grid%light_mass (a fraction of the mass of a node
!> inside the material) and that has a heavier neighbour (the 3**dim box around it) is no
!> unknown of its own for the step: its velocity and acceleration are the mass-weighted mean
!> of those of its heavy neighbours, v_l = sum_j c_j v_j (c_j = m_j / sum_k m_k), and its
!> mass, momentum and forces go to them in the same proportions (m_j += c_j m_l, ...). That
!> is P2G and G2P with the shape functions N'_j = N_j + sum_l c_jl N_l, constant within the
!> step: the same N' both ways, so the force is still the adjoint of the strain rate and the
!> stresses do no work the kinetic energy does not see (the FLIP balance of
!> docs/study/cantilever.md, finding 4); sum_j c_jl = 1 keeps the partition of unity, so a
!> moving particle on a light node is not strained by it (a node held at rest strains it by
!> -v dN_l), and no node of tiny mass gives a particle its own stress back as a large
!> acceleration (the root of the bspline2 cantilever, docs/study/cantilever.md). A held
!> component (boundary condition) of a light node stays at rest: its force there is the
!> support's. Light nodes without a heavy neighbour keep the treatment of their mass (empty
!> below grid%small_mass).
!>
!> On a grid cut among images (mpm_decomposition) every light node is treated by one image:
!> the one whose layers 1 .. n - layers along the cut axis hold it (0 and n - 1 too at an
!> end without a neighbour), so its 3**dim box is on that image with the whole sums of
!> halo_sum, and it takes the decisions of the whole grid. Its folds reach the other images
!> as increments of the shared layers (`light_increments`), added in image order (the left
!> image's first: the same bits on both), and its slaved values overwrite theirs
!> (`light_slaved_values`): every node two images hold ends with the same bits on both,
!> equal to those of one image to round-off (the order of the sums differs).
!>
!> A kernel: it works on this image's grid only. The step (mpm_halo: `settle_light_nodes`,
!> `fold_light`, `slave_light`) calls it and trades the shared layers between images.
module mpm_kernel_light
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    implicit none
    private
    public :: find_light_nodes, fold_light_local, fold_light_mass_local, slave_light_local, &
        light_increments, light_slaved_values

contains

    !> The light nodes of the step and their masters, from the masses of P2G (the caller
    !> then folds their mass and momentum into the masters: mpm_halo::settle_light_nodes).
    subroutine find_light_nodes(grid, layers)
        type(grid_type), intent(inout) :: grid
            !! grid with mass and momentum set by P2G (and summed over the images)
        integer, intent(in) :: layers
            !! node layers shared at a cut (shape_type%halo_width)

        integer :: x, y, z, id, ix, iy, iz, nid, k, first, zlo, zhi, lo(3), hi(3), a
        real(wp) :: total

        grid%nlight = 0
        grid%light_layers = layers
        if (grid%light_mass <= 0.0_wp) return
        if (.not. allocated(grid%light_node)) then
            allocate (grid%light_node(64), grid%light_start(65), grid%light_master(64*27), &
                grid%light_coef(64*27))
        end if
        zlo = 0
        zhi = 0
        if (grid%dim == 3) then
            zlo = -1
            zhi = 1
        end if
        lo = grid%active_lo
        hi = min(grid%active_hi, grid%nn - 1)
        ! on a cut grid: the layers this image treats (the light nodes whose box it holds)
        a = grid%halo_axis
        if (a /= 0) then
            if (grid%halo_left > 0) lo(a) = max(lo(a), 1)
            if (grid%halo_right > 0) hi(a) = min(hi(a), grid%nn(a) - layers)
        end if
        k = 0
        do z = lo(3), hi(3)
            do y = lo(2), hi(2)
                do x = lo(1), hi(1)
                    id = 1 + x + grid%nn(1)*(y + grid%nn(2)*z)
                    if (grid%mass(id) <= 0.0_wp .or. grid%mass(id) > grid%light_mass) cycle
                    call reserve(grid, grid%nlight + 1, k + 27)
                    first = k + 1
                    total = 0.0_wp
                    do iz = max(z + zlo, 0), min(z + zhi, grid%nn(3) - 1)
                        do iy = max(y - 1, 0), min(y + 1, grid%nn(2) - 1)
                            do ix = max(x - 1, 0), min(x + 1, grid%nn(1) - 1)
                                nid = 1 + ix + grid%nn(1)*(iy + grid%nn(2)*iz)
                                if (grid%mass(nid) <= grid%light_mass) cycle
                                k = k + 1
                                grid%light_master(k) = nid
                                grid%light_coef(k) = grid%mass(nid)
                                total = total + grid%mass(nid)
                            end do
                        end do
                    end do
                    if (k < first) cycle
                    grid%light_coef(first:k) = grid%light_coef(first:k)/total
                    grid%nlight = grid%nlight + 1
                    grid%light_node(grid%nlight) = id
                    grid%light_start(grid%nlight) = first
                end do
            end do
        end do
        grid%light_start(grid%nlight + 1) = k + 1
    end subroutine find_light_nodes

    !> Give the mass of each light node to its masters, m_j += c_j m_l (m_l = 0 after), on a
    !> grid that is not cut.
    pure subroutine fold_light_mass_local(grid)
        type(grid_type), intent(inout) :: grid
            !! the grid with its light nodes found

        integer :: n, k, id

        do n = 1, grid%nlight
            id = grid%light_node(n)
            do k = grid%light_start(n), grid%light_start(n + 1) - 1
                grid%mass(grid%light_master(k)) = grid%mass(grid%light_master(k)) &
                    + grid%light_coef(k)*grid%mass(id)
            end do
            grid%mass(id) = 0.0_wp
        end do
    end subroutine fold_light_mass_local

    !> Grow the tables to hold nlight light nodes and nmasters masters.
    subroutine reserve(grid, nlight, nmasters)
        type(grid_type), intent(inout) :: grid
            !! the grid
        integer, intent(in) :: nlight, nmasters
            !! entries needed

        integer, allocatable :: itmp(:)
        real(wp), allocatable :: rtmp(:)

        if (size(grid%light_node) < nlight) then
            allocate (itmp(2*nlight))
            itmp(1:size(grid%light_node)) = grid%light_node
            call move_alloc(itmp, grid%light_node)
            allocate (itmp(2*nlight + 1))
            itmp(1:size(grid%light_start)) = grid%light_start
            call move_alloc(itmp, grid%light_start)
        end if
        if (size(grid%light_master) < nmasters) then
            allocate (itmp(2*nmasters))
            itmp(1:size(grid%light_master)) = grid%light_master
            call move_alloc(itmp, grid%light_master)
            allocate (rtmp(2*nmasters))
            rtmp(1:size(grid%light_coef)) = grid%light_coef
            call move_alloc(rtmp, grid%light_coef)
        end if
    end subroutine reserve

    !> Give the nodal field (dim, nnodes) of each light node to its masters, f_j += c_j f_l,
    !> and zero it there (a second call adds nothing); held components are the support's. On
    !> a grid that is not cut.
    pure subroutine fold_light_local(grid, field)
        type(grid_type), intent(in) :: grid
            !! the grid with its light nodes found
        real(wp), intent(inout) :: field(:, :)
            !! momentum or force

        integer :: n, k, id, dim

        dim = grid%dim
        do n = 1, grid%nlight
            id = grid%light_node(n)
            where (grid%constrained(:, id)) field(:, id) = 0.0_wp
            do k = grid%light_start(n), grid%light_start(n + 1) - 1
                field(1:dim, grid%light_master(k)) = field(1:dim, grid%light_master(k)) &
                    + grid%light_coef(k)*field(1:dim, id)
            end do
            field(:, id) = 0.0_wp
        end do
    end subroutine fold_light_local

    !> The nodal field (dim, nnodes) of each light node from its masters, f_l = sum_j c_j f_j
    !> (held components zero), for this image's light nodes.
    pure subroutine slave_light_local(grid, field)
        type(grid_type), intent(in) :: grid
            !! the grid with its light nodes found
        real(wp), intent(inout) :: field(:, :)
            !! velocity or acceleration

        integer :: n, k, id, dim

        dim = grid%dim
        do n = 1, grid%nlight
            id = grid%light_node(n)
            field(:, id) = 0.0_wp
            do k = grid%light_start(n), grid%light_start(n + 1) - 1
                field(1:dim, id) = field(1:dim, id) &
                    + grid%light_coef(k)*field(1:dim, grid%light_master(k))
            end do
            where (grid%constrained(:, id)) field(:, id) = 0.0_wp
        end do
    end subroutine slave_light_local

    !> fold_light on a cut grid, this image's part: the increments its light nodes' folds
    !> make, delta_j = c_j f_l at the masters and -f_l at the light node (the light node
    !> keeps nothing: f + (-f) is 0 whatever the order); the caller trades the shared layers
    !> and adds them in image order (mpm_halo::fold_light).
    pure subroutine light_increments(grid, field, held, delta)
        type(grid_type), intent(in) :: grid
            !! the cut grid with this image's light nodes found
        real(wp), intent(in) :: field(:, :)
            !! mass (1, nnodes), momentum or force (dim, nnodes)
        logical, intent(in) :: held
            !! the rows are the grid's components: held components of a light node give
            !! nothing
        real(wp), intent(out) :: delta(:, :)
            !! the increments, the shape of field

        real(wp) :: part(size(field, 1))
        integer :: n, k, id

        delta = 0.0_wp
        do n = 1, grid%nlight
            id = grid%light_node(n)
            part = field(:, id)
            if (held) then
                where (grid%constrained(:, id)) part = 0.0_wp
            end if
            do k = grid%light_start(n), grid%light_start(n + 1) - 1
                delta(:, grid%light_master(k)) = delta(:, grid%light_master(k)) &
                    + grid%light_coef(k)*part
            end do
            delta(:, id) = -field(:, id)
        end do
    end subroutine light_increments

    !> slave_light on a cut grid, this image's part: per node a flag (1: one of this image's
    !> light nodes) and its slaved values, for the neighbours (mpm_halo::slave_light).
    pure subroutine light_slaved_values(grid, field, mine)
        type(grid_type), intent(in) :: grid
            !! the cut grid with this image's light nodes found and slaved
        real(wp), intent(in) :: field(:, :)
            !! velocity or acceleration (dim, nnodes)
        real(wp), intent(out) :: mine(:, :)
            !! (dim + 1, nnodes): the flag and the values

        integer :: n

        mine = 0.0_wp
        do n = 1, grid%nlight
            mine(1, grid%light_node(n)) = 1.0_wp
            mine(2:, grid%light_node(n)) = field(:, grid%light_node(n))
        end do
    end subroutine light_slaved_values

end module mpm_kernel_light
