!> Per-step particle stencils, the particle order by cell layer and the scatter chunks.
!>
!> Every pass of a step (P2G, G2P, MUSL remap, stress update) uses the shape functions at the
!> start-of-step positions, so they are evaluated once per step (`compute_stencils`) and kept
!> as 1D factors: for particle p and axis a, the first node `first(a, p)` and the weights
!> `w(k, a, p)` of nodes first .. first + nper(a) - 1 and the derivatives `dw(k, a, p)` of all
!> but the last of them: the weights sum to one, so the derivative of the last is minus the
!> sum of the others (`axis_factors`; 16 bytes per particle less in 2D, 24 in 3D). Every
!> kept node is inside the grid (the stencil is shifted where it reaches past a face, the
!> nodes it drops having zero weight), so the passes need no bounds checks. Derivatives of
!> zero weights are zero, as the stencils of `mpm_shape` skip those nodes.
!>
!> Threads without atomics or locks, and the same sums with any number of threads: the
!> particles are sorted by their cell's layer along the slowest axis (z in 3D, y in 2D; a
!> parallel counting sort over fixed blocks, stable: a fixed order for a given state) and cut
!> into chunks of equal particle count whose number depends on the particle count only.
!> A scatter pass (P2G, remap) sums each chunk into its own buffer, which spans the node
!> layers of the chunk along the slowest axis (contiguous node indices);
!> the buffers are then folded into the grid node by node in chunk order. The order of every
!> sum is therefore fixed, and a run gives the same bits on 1, 2 or 64 threads.
module mpm_stencil
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_other, exit_numerical
    use mpm_strings, only: int_text
    use mpm_grid, only: grid_type
    use mpm_particles, only: particles_type, particle_number
    use mpm_particle_domain, only: domain_half_sizes_block
    use mpm_shape, only: shape_type, full_shape_type, max_nodes_per_axis
    implicit none
    private
    public :: stencils_type, compute_stencils, particle_nodes, particle_weights, stencil_bytes, axis_derivatives, &
        axis_derivatives_any, fixed_width, sort_stencils, restencil, chunk_holds, cut_chunks

    integer, parameter :: fixed_width = 3
        !! widest stencil the kernels with scratch of fixed size serve (constant-width loops
        !! of widths 2 and 3, narrow grids): axis_derivatives

    integer, parameter :: stencil_block = 256
        !! particles per block of the weights and the stencils' own work
    integer, parameter :: particles_per_chunk = 2048
        !! particles per chunk of a scatter pass (at least; fewer chunks for small runs)
    integer, parameter :: max_chunks = 32
        !! chunks of a scatter pass at most (load balance for up to ~16 threads)
    integer, parameter :: sort_block_particles = 4096
        !! particles per block of the parallel counting sort (at least)
    integer, parameter :: max_sort_blocks = 32
        !! blocks of the counting sort at most

    !> Stencils of all particles for one step, their order and the scatter chunks.
    type :: stencils_type
        integer :: n = 0
            !! particles
        integer :: dim = 2
            !! space dimensions
        integer :: nps = 3
            !! nodes per axis of the shape function (its support width, nodes_per_axis)
        integer :: nper(3) = 1
            !! nodes kept per axis: nps, less on an axis of the grid with fewer nodes; 1 on
            !! axis 3 in 2D
        integer :: width = 0
            !! nps when every axis keeps all nps nodes (the kernels then run the loops of
            !! constant length of that width, when they have them), 0 otherwise
        integer :: count = 1
            !! nodes per particle, product(nper)
        integer :: stride(3) = 0
            !! node index step along each axis: 1, nn(1), nn(1) nn(2)
        integer :: slow = 2
            !! slowest axis of the node numbering (dim)
        integer, allocatable :: first(:, :)
            !! first node per axis, 0-based (dim, n)
        real(wp), allocatable :: w(:, :, :)
            !! 1D weights (nps, dim, n) [-]
        real(wp), allocatable :: dw(:, :, :)
            !! 1D weight derivatives of the first nps - 1 nodes (nps - 1, dim, n) [1/m]
        integer, allocatable :: window(:)
            !! per particle, the window of its nonzero weights when the stencils are tensor
            !! products of width 3 (`nonzero_windows`): bits 0 .. dim - 1 set where an axis keeps
            !! 2 nodes, bits 3 .. 2 + dim where the window starts one node past `first` (n)
        logical :: tensor = .true.
            !! the weights are products of the 1D factors w, dw; false for a shape function
            !! that is no tensor product (mpm_shape::full_shape_type, CPDI), whose weights
            !! and gradients of the nodes of the box first .. first + nper - 1 are wn, dwn
        real(wp), allocatable :: wn(:, :)
            !! weights of the box's nodes, x fastest (count, n) [-]; only when not tensor
        real(wp), allocatable :: dwn(:, :, :)
            !! their gradients (dim, count, n) [1/m]; only when not tensor
        integer, allocatable :: order(:)
            !! particles sorted by cell layer along the slowest axis, then by index (n)
        integer :: nchunks = 0
            !! chunks of the scatter passes
        integer, allocatable :: chunk_start(:)
            !! chunk k holds order(chunk_start(k) : chunk_start(k + 1) - 1)
        integer, allocatable :: chunk_lo(:), chunk_hi(:)
            !! first and last node layer (0-based, slowest axis) that chunk k touches
        integer, allocatable :: chunk_offset(:)
            !! buffer entries of chunk k start after chunk_offset(k); chunk_offset(nchunks + 1)
            !! is the buffer size
        integer :: margin = 0
            !! node layers and nodes the scatter layout (chunk layers, box) adds on every side
            !! of the stencils: 1 in a one-pass step, whose scatter takes the stencils after
            !! the moves (a particle moves less than a cell per step)
        integer :: layer_lo = 0, layer_hi = -1
            !! node layers (slowest axis) that some chunk touches
        integer :: box_lo(3) = 0, box_hi(3) = -1
            !! the box of nodes (0-based, per axis; 0 : 0 on axis 3 in 2D) that some particle
            !! touches: the grid work of the step (scatter buffers, fold, nodal update)
        integer :: bstride(3) = 0
            !! index step of the scatter buffers along each axis: 1, the box's width along x,
            !! its width along x times its width along y (3D); 0 on axis 3 in 2D
        integer, allocatable :: chunk_base(:)
            !! node (x, y, z) of chunk k's layers is entry chunk_base(k) + 1 + x
            !! + bstride(2) y + bstride(3) z of the scatter buffer
        integer, allocatable :: layer_chunks(:, :)
            !! first and last chunk touching each node layer (2, 0:nn(slow) - 1); first > last
            !! when none does
        integer, allocatable :: histogram(:)
            !! scratch of the counting sort (cell layers x blocks)
        logical :: with_cells = .false.
            !! whether `cell` is kept (F-bar)
        integer, allocatable :: cell(:)
            !! cell of each particle at the start of the step, 1-based linear index (n); only
            !! when asked for (F-bar averages per cell)
    end type stencils_type

contains

    !> Evaluate the stencils of every particle at its current position, sort the particles by
    !> cell layer (or take the order given) and cut the chunks of the scatter passes.
    subroutine compute_stencils(stc, grid, particles, shape, error, cells, margin, order)
        type(stencils_type), intent(inout) :: stc
            !! stencils (allocated on first use and when the particle count changes)
        type(grid_type), intent(in) :: grid
            !! the grid
        type(particles_type), intent(in) :: particles
            !! particles at the start of the step
        class(shape_type), intent(in) :: shape
            !! shape function
        type(error_type), allocatable, intent(out) :: error
            !! set when the scratch cannot be allocated
        logical, intent(in), optional :: cells
            !! also keep the cell of each particle (stc%cell; F-bar)
        integer, intent(in), optional :: margin
            !! node layers and nodes the scatter layout adds around the stencils (stc%margin;
            !! default 0)
        integer, intent(in), optional :: order(:)
            !! the particle order of the scatter passes instead of the sorted one (a restart
            !! of a one-pass run: the order its last scatter took)

        integer :: nps, bad, p0, p1

        nps = shape%nodes_per_axis()
        stc%with_cells = .false.
        if (present(cells)) stc%with_cells = cells
        select type (shape)
        class is (full_shape_type)
            stc%tensor = .false.
        class default
            stc%tensor = .true.
        end select
        call allocate_stencils(stc, grid, particles%n, nps, error)
        if (allocated(error)) return
        stc%margin = 0
        if (present(margin)) stc%margin = margin
        select type (shape)
        class is (full_shape_type)
            ! weights and gradients per node of the box (CPDI)
            call shape%weights_full(grid, particles%x, particles%f, particles%lp0, stc%nper, &
                stc%first, stc%wn, stc%dwn, bad)
            if (bad > 0) then
                call domain_error(grid, particles, bad, stc%nper, error)
                return
            end if
        class default
            ! tensor-product shapes: their weights are evaluated block by block below
        end select
        ! block by block: the weights of a block (the shape function's weights_all), then
        ! what the stencils keep of them while they are in the cache
        !$omp parallel do default(none) schedule(static) shared(stc, grid, particles, shape) &
        !$omp private(p0, p1)
        do p0 = 1, particles%n, stencil_block
            p1 = min(p0 + stencil_block - 1, particles%n)
            call block_stencils(stc, grid, particles, shape, p0, p1)
        end do
        !$omp end parallel do

        if (present(order)) then
            stc%order = order
            call cut_chunks(stc, grid)
        else
            call sort_stencils(stc, grid, particles)
        end if
    end subroutine compute_stencils

    !> The stencils of the particles p0 .. p1 (at most stencil_block) at their positions: the
    !> weights of the block (the shape function's weights_all; tensor products), then what
    !> the stencils keep of them while they are in the cache; the cells too when kept.
    subroutine block_stencils(stc, grid, particles, shape, p0, p1)
        type(stencils_type), intent(inout) :: stc
            !! stencils; those of the block are replaced
        type(grid_type), intent(in) :: grid
            !! the grid
        type(particles_type), intent(in) :: particles
            !! particles
        class(shape_type), intent(in) :: shape
            !! shape function
        integer, intent(in) :: p0, p1
            !! the block

        integer :: p, dim, nps
        real(wp) :: lp2(2, stencil_block), lp3(3, stencil_block)

        dim = stc%dim
        nps = stc%nps
        if (stc%tensor .and. shape%initial_domain()) then
            ! uGIMP: the particle domain at its initial size
            call shape%weights_all(grid, particles%x(:, p0:p1), particles%lp0(:, p0:p1), &
                stc%first(:, p0:p1), stc%w(:, :, p0:p1), stc%dw(:, :, p0:p1))
        else if (stc%tensor) then
            ! the domain half-sizes from F (they are not kept between steps)
            ! (scratch of the dimension's extent: a section lp3(1:2, :) would be copied)
            if (dim == 2) then
                call domain_half_sizes_block(2, p1 - p0 + 1, particles%f(:, :, p0:p1), &
                    particles%lp0(:, p0:p1), lp2)
                call shape%weights_all(grid, particles%x(:, p0:p1), lp2(:, 1:p1 - p0 + 1), &
                    stc%first(:, p0:p1), stc%w(:, :, p0:p1), stc%dw(:, :, p0:p1))
            else
                call domain_half_sizes_block(3, p1 - p0 + 1, particles%f(:, :, p0:p1), &
                    particles%lp0(:, p0:p1), lp3)
                call shape%weights_all(grid, particles%x(:, p0:p1), lp3(:, 1:p1 - p0 + 1), &
                    stc%first(:, p0:p1), stc%w(:, :, p0:p1), stc%dw(:, :, p0:p1))
            end if
        end if
        if (stc%tensor) then
            ! keep the stencils inside the grid: the nodes they drop have zero weight
            call keep_inside(nps, dim, p1 - p0 + 1, grid%nn, stc%nper, stc%first(:, p0:p1), &
                stc%w(:, :, p0:p1), stc%dw(:, :, p0:p1))
            if (windowed(stc)) call nonzero_windows(dim, p1 - p0 + 1, stc%w(:, :, p0:p1), &
                stc%window(p0:p1))
        end if
        if (stc%with_cells) then
            do p = p0, p1
                stc%cell(p) = particle_cell(grid, particles%x(:, p))
            end do
        end if
    end subroutine block_stencils

    !> The cell of a position, 1-based linear index (clamped to the grid).
    pure integer function particle_cell(grid, x)
        type(grid_type), intent(in) :: grid
            !! the grid
        real(wp), intent(in) :: x(:)
            !! position (dim) [m]

        integer :: a, stride

        particle_cell = 1
        stride = 1
        do a = 1, grid%dim
            particle_cell = particle_cell + axis_cell(grid, x(a), a)*stride
            stride = stride*grid%ncells(a)
        end do
    end function particle_cell

    !> Sort the particles by the cell layer of their positions along the slowest axis and cut
    !> the chunks of the scatter passes (stencils evaluated at those positions).
    subroutine sort_stencils(stc, grid, particles)
        type(stencils_type), intent(inout) :: stc
            !! stencils of the particles at their positions
        type(grid_type), intent(in) :: grid
            !! the grid
        type(particles_type), intent(in) :: particles
            !! particles

        integer :: p, k, dim, c, q, nlayers, nb, b

        dim = grid%dim
        ! counting sort by node layer of the cell along the slowest axis, in parallel over
        ! fixed blocks of particles: stable (by layer, then particle index), so the order is
        ! fixed for a given state whatever the number of threads
        nlayers = grid%ncells(dim)
        nb = max(1, min(max_sort_blocks, particles%n/sort_block_particles))
        if (allocated(stc%histogram)) then
            if (size(stc%histogram) /= nlayers*nb) deallocate (stc%histogram)
        end if
        if (.not. allocated(stc%histogram)) allocate (stc%histogram(nlayers*nb))
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(stc, grid, particles, nb, nlayers, dim) private(b, p, k)
        do b = 1, nb
            stc%histogram((b - 1)*nlayers + 1:b*nlayers) = 0
            do p = block_start(particles%n, nb, b), block_start(particles%n, nb, b + 1) - 1
                k = (b - 1)*nlayers + 1 + axis_cell(grid, particles%x(dim, p), dim)
                stc%histogram(k) = stc%histogram(k) + 1
            end do
        end do
        !$omp end parallel do
        q = 1
        do c = 1, nlayers
            do b = 1, nb
                k = stc%histogram((b - 1)*nlayers + c)
                stc%histogram((b - 1)*nlayers + c) = q
                q = q + k
            end do
        end do
        !$omp parallel do default(none) schedule(static) &
        !$omp shared(stc, grid, particles, nb, nlayers, dim) private(b, p, k, q)
        do b = 1, nb
            do p = block_start(particles%n, nb, b), block_start(particles%n, nb, b + 1) - 1
                k = (b - 1)*nlayers + 1 + axis_cell(grid, particles%x(dim, p), dim)
                q = stc%histogram(k)
                stc%order(q) = p
                stc%histogram(k) = q + 1
            end do
        end do
        !$omp end parallel do
        call cut_chunks(stc, grid)
    end subroutine sort_stencils

    !> Evaluate again the stencils of the particles `idx` at their current positions (a
    !> one-pass step: the particles of a chunk after their moves, for the scatter of the next
    !> step); tensor-product shape functions. The particles' positions, deformation gradients
    !> and initial half-sizes are copied to scratch, the weights of the copy evaluated and
    !> kept as compute_stencils keeps them (the same bits: the same operations on the same
    !> values), and the stencils written back. The order and the chunks are not changed.
    subroutine restencil(stc, grid, particles, shape, idx)
        type(stencils_type), intent(inout) :: stc
            !! stencils; those of the particles idx are replaced
        type(grid_type), intent(in) :: grid
            !! the grid
        type(particles_type), intent(in) :: particles
            !! particles
        class(shape_type), intent(in) :: shape
            !! shape function (a tensor product)
        integer, intent(in) :: idx(:)
            !! the particles

        integer, parameter :: block = 64
            !! particles per block of scratch
        integer :: i0, nb, i, p, dim, nps
        integer :: first(stc%dim, block), window(block)
        real(wp) :: x(stc%dim, block), f(stc%dim, stc%dim, block), lp0(stc%dim, block), &
            lp(stc%dim, block), w(stc%nps, stc%dim, block), dw(stc%nps - 1, stc%dim, block)
        logical :: initial

        dim = stc%dim
        nps = stc%nps
        if (size(idx) == 0) return
        if (size(idx) <= stencil_block .and. idx(size(idx)) - idx(1) == size(idx) - 1) then
            ! consecutive particles (the common case: the order follows the particle numbers
            ! within a cell layer): on the particle arrays themselves
            if (all(idx(2:) - idx(:size(idx) - 1) == 1)) then
                call block_stencils(stc, grid, particles, shape, idx(1), idx(size(idx)))
                return
            end if
        end if
        initial = shape%initial_domain()
        do i0 = 1, size(idx), block
            nb = min(block, size(idx) - i0 + 1)
            ! copies of sizes known here (a runtime-sized one calls memmove)
            if (dim == 2) then
                do i = 1, nb
                    p = idx(i0 + i - 1)
                    x(1:2, i) = particles%x(1:2, p)
                    lp0(1:2, i) = particles%lp0(1:2, p)
                    if (.not. initial) f(1:2, 1:2, i) = particles%f(1:2, 1:2, p)
                end do
            else
                do i = 1, nb
                    p = idx(i0 + i - 1)
                    x(1:3, i) = particles%x(1:3, p)
                    lp0(1:3, i) = particles%lp0(1:3, p)
                    if (.not. initial) f(1:3, 1:3, i) = particles%f(1:3, 1:3, p)
                end do
            end if
            if (initial) then
                lp(:, 1:nb) = lp0(:, 1:nb)
            else
                call domain_half_sizes_block(dim, nb, f(:, :, 1:nb), lp0(:, 1:nb), lp(:, 1:nb))
            end if
            call shape%weights_all(grid, x(:, 1:nb), lp(:, 1:nb), first(:, 1:nb), &
                w(:, :, 1:nb), dw(:, :, 1:nb))
            call keep_inside(nps, dim, nb, grid%nn, stc%nper, first(:, 1:nb), &
                w(:, :, 1:nb), dw(:, :, 1:nb))
            if (windowed(stc)) then
                call nonzero_windows(dim, nb, w(:, :, 1:nb), window(1:nb))
                do i = 1, nb
                    stc%window(idx(i0 + i - 1)) = window(i)
                end do
            end if
            if (dim == 2 .and. nps == 3) then
                do i = 1, nb
                    p = idx(i0 + i - 1)
                    stc%first(1:2, p) = first(1:2, i)
                    stc%w(1:3, 1:2, p) = w(1:3, 1:2, i)
                    stc%dw(1:2, 1:2, p) = dw(1:2, 1:2, i)
                end do
            else if (dim == 3 .and. nps == 3) then
                do i = 1, nb
                    p = idx(i0 + i - 1)
                    stc%first(1:3, p) = first(1:3, i)
                    stc%w(1:3, 1:3, p) = w(1:3, 1:3, i)
                    stc%dw(1:2, 1:3, p) = dw(1:2, 1:3, i)
                end do
            else
                do i = 1, nb
                    p = idx(i0 + i - 1)
                    stc%first(:, p) = first(:, i)
                    stc%w(:, :, p) = w(:, :, i)
                    stc%dw(:, :, p) = dw(:, :, i)
                end do
            end if
            if (stc%with_cells) then
                do i = 1, nb
                    p = idx(i0 + i - 1)
                    stc%cell(p) = particle_cell(grid, particles%x(:, p))
                end do
            end if
        end do
    end subroutine restencil

    !> Whether the stencils of the particles order(qlo:qhi) of chunk k lie inside the chunk's
    !> part of the scatter layout: its node layers along the slowest axis and the box along
    !> the others.
    pure logical function chunk_holds(stc, k, qlo, qhi)
        type(stencils_type), intent(in) :: stc
            !! stencils, order and chunks
        integer, intent(in) :: k, qlo, qhi
            !! the chunk and its range of the order

        integer :: q, p, a, lo(3), hi(3)

        lo = stc%box_lo
        hi = stc%box_hi
        lo(stc%slow) = stc%chunk_lo(k)
        hi(stc%slow) = stc%chunk_hi(k)
        do a = 1, stc%dim
            hi(a) = hi(a) - stc%nper(a) + 1
        end do
        chunk_holds = .true.
        do q = qlo, qhi
            p = stc%order(q)
            do a = 1, stc%dim
                chunk_holds = chunk_holds .and. stc%first(a, p) >= lo(a) .and. &
                    stc%first(a, p) <= hi(a)
            end do
        end do
    end function chunk_holds

    !> The error of a particle whose full (CPDI) stencil does not fit its box: its domain,
    !> the image of its initial box under F, spans more than the box's nodes along an axis,
    !> or F has turned it inside out (det F <= 0). A numerical failure of the run (exit 3).
    subroutine domain_error(grid, particles, p, nper, error)
        type(grid_type), intent(in) :: grid
        type(particles_type), intent(in) :: particles
        integer, intent(in) :: p, nper(3)
        type(error_type), allocatable, intent(out) :: error

        integer :: a, b, dim
        real(wp) :: span(3), det
        character(len=:), allocatable :: spans
        character(len=32) :: text

        dim = grid%dim
        span = 0.0_wp
        do a = 1, dim
            do b = 1, dim
                span(a) = span(a) + 2.0_wp*abs(particles%f(a, b, p))*particles%lp0(b, p)
            end do
        end do
        if (dim == 2) then
            det = particles%f(1, 1, p)*particles%f(2, 2, p) - particles%f(1, 2, p)*particles%f(2, 1, p)
        else
            det = particles%f(1, 1, p)*(particles%f(2, 2, p)*particles%f(3, 3, p) &
                - particles%f(2, 3, p)*particles%f(3, 2, p)) &
                - particles%f(1, 2, p)*(particles%f(2, 1, p)*particles%f(3, 3, p) &
                - particles%f(2, 3, p)*particles%f(3, 1, p)) &
                + particles%f(1, 3, p)*(particles%f(2, 1, p)*particles%f(3, 2, p) &
                - particles%f(2, 2, p)*particles%f(3, 1, p))
        end if
        spans = ""
        do a = 1, dim
            write (text, "(f0.2)") span(a)/grid%dx
            if (a > 1) spans = spans//", "
            spans = spans//trim(text)
        end do
        write (text, "(es10.3)") det
        text = adjustl(text)
        call fatal_error(error, "particle "//int_text(particle_number(particles, p))//": its CPDI domain "// &
            "does not fit the "//int_text(nper(1))//" nodes per axis of its stencil (it spans "// &
            spans//" cells along the axes, det F = "//trim(text)//"; a domain may span "// &
            "corners in three consecutive cells and must not be inverted): the particle is "// &
            "stretched beyond what CPDI1 represents; a finer particle spacing (more particles "// &
            "per cell) or another shape function (solver.shape_function) avoids it", exit_numerical)
    end subroutine domain_error

    !> The stencils of a block of n particles kept inside the grid: a stencil that reaches
    !> past a grid end moves its first node inside (shift_factors; the nodes it drops have
    !> zero weight), and the derivative of a node of zero weight is zero (exactly; without
    !> branches: where a weight is zero depends on the position). On the block's arrays as
    !> plain arrays (their addresses known once, not reloaded from the stencils after every
    !> store).
    pure subroutine keep_inside(nps, dim, n, nn, nper, first, w, dw)
        integer, intent(in) :: nps, dim, n
            !! nodes per axis of the shape function, space dimensions, particles
        integer, intent(in) :: nn(3), nper(3)
            !! nodes of the grid per axis, nodes of the stencils per axis
        integer, intent(inout) :: first(dim, n)
            !! first node per axis (0-based)
        real(wp), intent(inout) :: w(nps, dim, n)
            !! weights [-]
        real(wp), intent(inout) :: dw(nps - 1, dim, n)
            !! derivatives of the first nps - 1 nodes [1/m]

        integer :: p, a, k, shift
        logical :: shifts

        ! a shift is rare (a particle next to a grid end): looked for in the whole block first
        shifts = .false.
        do a = 1, dim
            shifts = shifts .or. nper(a) < nps .or. minval(first(a, :)) < 0 .or. &
                maxval(first(a, :)) > nn(a) - nper(a)
        end do
        if (shifts) then
            do p = 1, n
                do a = 1, dim
                    shift = max(0, min(first(a, p), nn(a) - nper(a))) - first(a, p)
                    if (shift /= 0 .or. nper(a) < nps) then
                        call shift_factors(w(:, a, p), dw(:, a, p), shift, nper(a))
                        first(a, p) = first(a, p) + shift
                    end if
                end do
            end do
        end if
        if (nps == 3) then
            call zero_derivatives_3(dim*n, w, dw)
        else
            do p = 1, n
                do a = 1, dim
                    do k = 1, nps - 1
                        dw(k, a, p) = merge(dw(k, a, p), 0.0_wp, w(k, a, p) > 0.0_wp)
                    end do
                end do
            end do
        end if
    end subroutine keep_inside

    !> keep_inside's zero derivatives at the nodes of zero weight for stencils of 3 nodes per
    !> axis, over the m = dim n axes of a block (the loop of constant length unrolled).
    pure subroutine zero_derivatives_3(m, w, dw)
        integer, intent(in) :: m
            !! axes of the block (dim times its particles)
        real(wp), intent(in) :: w(3, m)
            !! weights [-]
        real(wp), intent(inout) :: dw(2, m)
            !! derivatives of the first 2 nodes [1/m]

        integer :: j

        do j = 1, m
            dw(1, j) = merge(dw(1, j), 0.0_wp, w(1, j) > 0.0_wp)
            dw(2, j) = merge(dw(2, j), 0.0_wp, w(2, j) > 0.0_wp)
        end do
    end subroutine zero_derivatives_3

    !> The window of each particle's stencil of width 3 that holds its nonzero weights: along
    !> each axis the 3 nodes, or 2 when the first or the last weight is zero (a cpGIMP domain
    !> inside one cell: at 2 particles per cell about half of the particles and axes of a flow,
    !> all of them in an undeformed body). The kernels then skip the node of zero weight and
    !> zero derivative, whose products add nothing. Bit a - 1 of the result is set when axis a
    !> keeps 2 nodes, bit 2 + a when its window starts one node past `first` (the first weight
    !> is the zero one); stored per particle and step in stc%window. For a block of n particles.
    pure subroutine nonzero_windows(dim, n, w, window)
        integer, intent(in) :: dim, n
            !! space dimensions, particles
        real(wp), intent(in) :: w(3, dim, n)
            !! weights [-]
        integer, intent(out) :: window(n)
            !! the window of each particle

        integer :: p, a, bits
        logical :: zero_first, zero_last

        do p = 1, n
            bits = 0
            do a = 1, dim
                ! exact zeros only: a weight of round-off size still counts
                zero_first = w(1, a, p) == 0.0_wp
                zero_last = w(3, a, p) == 0.0_wp
                bits = bits + merge(2**(a - 1), 0, zero_first .or. zero_last) &
                    + merge(2**(2 + a), 0, zero_first .and. .not. zero_last)
            end do
            window(p) = bits
        end do
    end subroutine nonzero_windows

    !> The 1D factors of one particle and axis moved by `shift` nodes (node k takes what node
    !> k + shift had), only the first `kept` nodes kept, the others zero.
    pure subroutine shift_factors(w, dw, shift, kept)
        real(wp), intent(inout) :: w(:)
            !! weights (nps) [-]
        real(wp), intent(inout) :: dw(:)
            !! derivatives of the first nps - 1 nodes [1/m]
        integer, intent(in) :: shift
            !! nodes to move by
        integer, intent(in) :: kept
            !! nodes kept

        integer :: k, nps
        real(wp) :: w0(size(w)), dw0(size(w))

        nps = size(w)
        w0 = w
        dw0(1:nps - 1) = dw
        dw0(nps) = -sum(dw0(1:nps - 1))
        do k = 1, nps
            if (k + shift >= 1 .and. k + shift <= nps .and. k <= kept) then
                w(k) = w0(k + shift)
                if (k < nps) dw(k) = dw0(k + shift)
            else
                w(k) = 0.0_wp
                if (k < nps) dw(k) = 0.0_wp
            end if
        end do
    end subroutine shift_factors

    !> Cell index (0-based) along axis a of a coordinate, clamped to the grid (int truncates
    !> towards zero: the same cell as floor after the clamp).
    pure integer function axis_cell(grid, x, a)
        type(grid_type), intent(in) :: grid
            !! the grid
        real(wp), intent(in) :: x
            !! coordinate along axis a [m]
        integer, intent(in) :: a
            !! axis
        axis_cell = min(max(int((x - grid%origin(a))/grid%dx), 0), grid%ncells(a) - 1)
    end function axis_cell

    !> First particle of block b of nb blocks of n particles (block_start(n, nb, nb + 1) = n + 1).
    pure integer function block_start(n, nb, b)
        integer, intent(in) :: n, nb, b
        block_start = 1 + int((int(b - 1, 8)*n)/nb)
    end function block_start

    !> Allocate the per-particle arrays and the chunk tables.
    subroutine allocate_stencils(stc, grid, n, nps, error)
        type(stencils_type), intent(inout) :: stc
        type(grid_type), intent(in) :: grid
        integer, intent(in) :: n, nps
        type(error_type), allocatable, intent(out) :: error

        integer :: stat, dim, a
        character(len=256) :: msg

        dim = grid%dim
        stc%dim = dim
        stc%nps = nps
        stc%nper = 1
        do a = 1, dim
            stc%nper(a) = min(nps, grid%nn(a))
        end do
        stc%width = 0
        if (all(stc%nper(1:dim) == nps)) stc%width = nps
        stc%count = product(stc%nper)
        stc%stride = [1, grid%nn(1), grid%nn(1)*grid%nn(2)]
        stc%slow = dim
        if (allocated(stc%first) .and. stc%n == n) then
            if (size(stc%w, 1) == nps .and. (allocated(stc%cell) .eqv. stc%with_cells) .and. &
                (allocated(stc%wn) .neqv. stc%tensor) .and. &
                (allocated(stc%window) .eqv. windowed(stc))) return
        end if
        if (allocated(stc%first)) deallocate (stc%first, stc%w, stc%dw, stc%order, &
            stc%layer_chunks)
        if (allocated(stc%cell)) deallocate (stc%cell)
        if (allocated(stc%window)) deallocate (stc%window)
        if (allocated(stc%wn)) deallocate (stc%wn, stc%dwn)
        stc%n = n
        allocate (stc%first(dim, n), stc%w(nps, dim, n), stc%dw(nps - 1, dim, n), stc%order(n), &
            stc%layer_chunks(2, 0:grid%nn(dim) - 1), stat=stat, errmsg=msg)
        if (stat == 0 .and. stc%with_cells) allocate (stc%cell(n), stat=stat, errmsg=msg)
        if (stat == 0 .and. windowed(stc)) allocate (stc%window(n), stat=stat, errmsg=msg)
        if (stat == 0 .and. .not. stc%tensor) allocate (stc%wn(stc%count, n), &
            stc%dwn(dim, stc%count, n), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the particle stencils: "//trim(msg), &
                exit_other)
            return
        end if
    end subroutine allocate_stencils

    !> Cut the sorted particles into chunks of equal count and find the node layers each
    !> touches along the slowest axis.
    subroutine cut_chunks(stc, grid)
        type(stencils_type), intent(inout) :: stc
        type(grid_type), intent(in) :: grid

        integer :: k, nc, q, p, lo, hi, s, layer, nlayers, cross, a, origin(3), lo3(3), hi3(3)

        s = stc%slow
        nc = max(1, min(max_chunks, stc%n/particles_per_chunk))
        if (stc%n == 0) nc = 0
        if (.not. allocated(stc%chunk_start)) then
            allocate (stc%chunk_start(max_chunks + 1), stc%chunk_lo(max_chunks), &
                stc%chunk_hi(max_chunks), stc%chunk_offset(max_chunks + 1), &
                stc%chunk_base(max_chunks))
        end if
        stc%nchunks = nc
        nlayers = grid%nn(s)
        ! the box of the nodes the particles touch (its extent along the slowest axis is that
        ! of the chunks, below)
        stc%box_lo = 0
        stc%box_hi = 0
        if (nc > 0) then
            stc%box_lo(1:stc%dim) = huge(1)
            stc%box_hi(1:stc%dim) = -huge(1)
        else
            stc%box_hi(1:stc%dim) = -1
        end if
        lo3 = stc%box_lo
        hi3 = stc%box_hi
        ! minima and maxima are exact: the same box with any number of threads
        !$omp parallel do default(none) schedule(static) shared(stc) private(p, a) &
        !$omp reduction(min: lo3) reduction(max: hi3)
        do p = 1, stc%n
            do a = 1, stc%dim
                lo3(a) = min(lo3(a), stc%first(a, p))
                hi3(a) = max(hi3(a), stc%first(a, p))
            end do
        end do
        !$omp end parallel do
        stc%box_lo = lo3
        stc%box_hi = hi3
        if (nc > 0) then
            do a = 1, stc%dim
                stc%box_lo(a) = max(stc%box_lo(a) - stc%margin, 0)
                stc%box_hi(a) = min(stc%box_hi(a) + stc%nper(a) - 1 + stc%margin, grid%nn(a) - 1)
            end do
        end if
        stc%bstride = 0
        stc%bstride(1) = 1
        stc%bstride(2) = stc%box_hi(1) - stc%box_lo(1) + 1
        if (stc%dim == 3) stc%bstride(3) = stc%bstride(2)*(stc%box_hi(2) - stc%box_lo(2) + 1)
        cross = stc%bstride(s)
        stc%layer_chunks(1, :) = huge(1)
        stc%layer_chunks(2, :) = -huge(1)
        stc%chunk_offset(1) = 0
        do k = 1, nc
            stc%chunk_start(k) = 1 + int((int(k - 1, 8)*stc%n)/nc)
        end do
        stc%chunk_start(nc + 1) = stc%n + 1
        do k = 1, nc
            lo = huge(1)
            hi = -huge(1)
            do q = stc%chunk_start(k), stc%chunk_start(k + 1) - 1
                p = stc%order(q)
                lo = min(lo, stc%first(s, p))
                hi = max(hi, stc%first(s, p))
            end do
            lo = max(lo - stc%margin, 0)
            hi = min(hi + stc%nper(s) - 1 + stc%margin, nlayers - 1)
            stc%chunk_lo(k) = lo
            stc%chunk_hi(k) = hi
            stc%chunk_offset(k + 1) = stc%chunk_offset(k) + (hi - lo + 1)*cross
            origin = stc%box_lo
            origin(s) = lo
            stc%chunk_base(k) = stc%chunk_offset(k) - origin(1) - stc%bstride(2)*origin(2) &
                - stc%bstride(3)*origin(3)
            do layer = lo, hi
                stc%layer_chunks(1, layer) = min(stc%layer_chunks(1, layer), k)
                stc%layer_chunks(2, layer) = max(stc%layer_chunks(2, layer), k)
            end do
        end do
        stc%layer_lo = 0
        stc%layer_hi = -1
        if (nc > 0) then
            stc%layer_lo = minval(stc%chunk_lo(1:nc))
            stc%layer_hi = maxval(stc%chunk_hi(1:nc))
            stc%box_lo(s) = stc%layer_lo
            stc%box_hi(s) = stc%layer_hi
        end if
    end subroutine cut_chunks

    !> Nodes, weights and gradients of particle p (the tensor product of its 1D factors), in
    !> the order x fastest: the nodes and weights of particle_weights, and the gradients of
    !> the same products (in 2D the z factors are 1 and 0, so the one loop nest gives the
    !> 2D products exactly and a zero third component).
    pure subroutine particle_nodes(stc, p, node, w, dw)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: p
            !! particle
        integer, intent(out) :: node(:)
            !! linear node indices (stc%count or more entries, first stc%count used)
        real(wp), intent(out) :: w(:)
            !! weights [-]
        real(wp), intent(out) :: dw(:, :)
            !! weight gradients (3, nodes) [1/m] (first dim components)

        integer :: i, j, k, c
        integer :: node_all(max_nodes_per_axis**3)
        real(wp) :: w_all(max_nodes_per_axis**3), wjk, wx(max_nodes_per_axis), &
            dwx(max_nodes_per_axis), wy(max_nodes_per_axis), dwy(max_nodes_per_axis), &
            wz(max_nodes_per_axis), dwz(max_nodes_per_axis)

        call particle_weights(stc, p, node_all, w_all)
        node(1:stc%count) = node_all(1:stc%count)
        w(1:stc%count) = w_all(1:stc%count)
        if (.not. stc%tensor) then
            dw(:, 1:stc%count) = 0.0_wp
            dw(1:stc%dim, 1:stc%count) = stc%dwn(:, :, p)
            return
        end if
        call axis_factors(stc, 1, p, stc%nper(1), wx, dwx)
        call axis_factors(stc, 2, p, stc%nper(2), wy, dwy)
        if (stc%dim == 3) then
            call axis_factors(stc, 3, p, stc%nper(3), wz, dwz)
        else
            wz(1) = 1.0_wp
            dwz(1) = 0.0_wp
        end if
        c = 0
        do k = 1, stc%nper(3)
            do j = 1, stc%nper(2)
                wjk = wy(j)*wz(k)
                do i = 1, stc%nper(1)
                    c = c + 1
                    dw(1, c) = dwx(i)*wjk
                    dw(2, c) = wx(i)*dwy(j)*wz(k)
                    dw(3, c) = wx(i)*wy(j)*dwz(k)
                end do
            end do
        end do
    end subroutine particle_nodes

    !> The nodes and weights of particle p, without the gradients (the hot paths that only ask
    !> which nodes a particle touches and how much: APIC's held-node test, contact gaps).
    !> Arrays of the fixed largest stencil, so the compiler sees contiguous scratch; each
    !> weight is the same product as in particle_nodes, bit for bit.
    pure subroutine particle_weights(stc, p, node, w)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: p
            !! particle
        integer, intent(out) :: node(max_nodes_per_axis**3)
            !! linear node indices (first stc%count used)
        real(wp), intent(out) :: w(max_nodes_per_axis**3)
            !! weights [-]

        integer :: i, j, k, c, base, basej
        real(wp) :: wjk

        if (.not. stc%tensor) then
            base = 1 + stc%first(1, p) + stc%stride(2)*stc%first(2, p)
            if (stc%dim == 3) base = base + stc%stride(3)*stc%first(3, p)
            c = 0
            do k = 1, stc%nper(3)
                do j = 1, stc%nper(2)
                    basej = base + stc%stride(2)*(j - 1) + stc%stride(3)*(k - 1)
                    do i = 1, stc%nper(1)
                        c = c + 1
                        node(c) = basej + i - 1
                    end do
                end do
            end do
            w(1:c) = stc%wn(1:c, p)
        else if (stc%dim == 2) then
            base = 1 + stc%first(1, p) + stc%stride(2)*stc%first(2, p)
            c = 0
            do j = 1, stc%nper(2)
                basej = base + stc%stride(2)*(j - 1)
                do i = 1, stc%nper(1)
                    c = c + 1
                    node(c) = basej + i - 1
                    w(c) = stc%w(i, 1, p)*stc%w(j, 2, p)
                end do
            end do
        else
            base = 1 + stc%first(1, p) + stc%stride(2)*stc%first(2, p) &
                + stc%stride(3)*stc%first(3, p)
            c = 0
            do k = 1, stc%nper(3)
                do j = 1, stc%nper(2)
                    wjk = stc%w(j, 2, p)*stc%w(k, 3, p)
                    basej = base + stc%stride(2)*(j - 1) + stc%stride(3)*(k - 1)
                    do i = 1, stc%nper(1)
                        c = c + 1
                        node(c) = basej + i - 1
                        w(c) = stc%w(i, 1, p)*wjk
                    end do
                end do
            end do
        end if
    end subroutine particle_weights

    !> The 1D weight derivatives of particle p along axis a, nodes 1 .. n (n = nper(a) <=
    !> fixed_width): the derivative of the last node is minus the sum of the others (zero
    !> when its weight is zero). For the kernels of widths up to fixed_width: scratch of that
    !> fixed size, which the optimiser compiles as main did (with an extent of n, the
    !> narrow-grid kernels fused their operations otherwise and changed in the last bits);
    !> axis_derivatives_any for any width.
    pure subroutine axis_derivatives(stc, a, p, n, dw)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: a
            !! axis
        integer, intent(in) :: p
            !! particle
        integer, intent(in) :: n
            !! nodes along the axis, stc%nper(a), at most fixed_width
        real(wp), intent(out) :: dw(fixed_width)
            !! derivatives (first n) [1/m]
        include "mpm_stencil_axis_derivatives.inc"
    end subroutine axis_derivatives

    !> axis_derivatives for any width (scratch of n nodes).
    pure subroutine axis_derivatives_any(stc, a, p, n, dw)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: a
            !! axis
        integer, intent(in) :: p
            !! particle
        integer, intent(in) :: n
            !! nodes along the axis, stc%nper(a)
        real(wp), intent(out) :: dw(n)
            !! derivatives [1/m]
        include "mpm_stencil_axis_derivatives.inc"
    end subroutine axis_derivatives_any

    !> Whether the kernels take the stencils by the window of their nonzero weights
    !> (`nonzero_windows`): tensor products of width 3 on a grid that keeps all 3 nodes per axis.
    pure logical function windowed(stc)
        type(stencils_type), intent(in) :: stc
            !! stencils (nps, nper, tensor set)
        windowed = stc%tensor .and. stc%width == 3
    end function windowed

    !> The 1D weights and derivatives of particle p along axis a, nodes 1 .. n (n = nper(a)),
    !> the derivatives from axis_derivatives.
    pure subroutine axis_factors(stc, a, p, n, w, dw)
        type(stencils_type), intent(in) :: stc
            !! stencils of the step
        integer, intent(in) :: a
            !! axis
        integer, intent(in) :: p
            !! particle
        integer, intent(in) :: n
            !! nodes along the axis, stc%nper(a)
        real(wp), intent(out) :: w(:)
            !! weights (first n) [-]
        real(wp), intent(out) :: dw(:)
            !! derivatives (first n) [1/m]

        w(1:n) = stc%w(1:n, a, p)
        call axis_derivatives_any(stc, a, p, n, dw(1:n))
    end subroutine axis_factors

    !> Bytes per particle of the stencils, the order and the cell scratch.
    pure integer function stencil_bytes(stc)
        type(stencils_type), intent(in) :: stc
            !! stencils of the run
        stencil_bytes = (storage_size(1.0_wp)/8)*(2*stc%nps - 1)*stc%dim &
            + (storage_size(1)/8)*(stc%dim + 1 + merge(1, 0, stc%with_cells) &
            + merge(1, 0, windowed(stc)))
        if (.not. stc%tensor) stencil_bytes = stencil_bytes &
            + (storage_size(1.0_wp)/8)*stc%count*(1 + stc%dim)
    end function stencil_bytes

end module mpm_stencil
