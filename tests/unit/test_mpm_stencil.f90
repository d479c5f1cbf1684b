!> The per-step stencils (mpm_stencil) on made-up grids and particles: the weights of every
!> particle sum to one and their gradients to zero, the 1D factors (with the derivative of the
!> last node rebuilt from the others) give the same nodes, weights and gradients as the
!> shape function's own tensor product (mpm_shape::evaluate, a second code path), the first
!> node of each axis is the shape's (floor(xi) linear, floor(xi - 1/2) cpGIMP) and every kept
!> node is inside the grid, the particles are ordered by cell layer along the slowest axis
!> (stable), and the scatter chunks cut that order into equal parts whose node layers and
!> box hold every node their particles touch. The fast-path width is the shape's, and 0 on a
!> grid with an axis of fewer nodes.
program test_mpm_stencil
    use mpm_kinds, only: wp
    use mpm_testing, only: test_suite_type, new_suite, check, finish
    use mpm_testing_grid, only: made_up_grid, dims
    use mpm_error, only: error_type
    use mpm_grid, only: grid_type
    use mpm_particles, only: particles_type
    use mpm_shape, only: shape_type, stencil_type
    use mpm_shape_linear, only: linear_shape_type
    use mpm_shape_gimp, only: gimp_shape_type
    use mpm_shape_ugimp, only: ugimp_shape_type
    use mpm_shape_bspline2, only: bspline2_shape_type
    use mpm_shape_bspline3, only: bspline3_shape_type
    use mpm_stencil, only: stencils_type, compute_stencils, particle_nodes
    implicit none

    type(test_suite_type) :: suite
    type(linear_shape_type) :: linear
    type(gimp_shape_type) :: gimp
    type(ugimp_shape_type) :: ugimp
    type(bspline2_shape_type) :: bspline2
    type(bspline3_shape_type) :: bspline3
    real(wp), parameter :: round_off = 100.0_wp*epsilon(1.0_wp)
    integer, parameter :: particles_per_chunk = 2048, max_chunks = 32
        !! mpm_stencil's chunk sizes (the expected chunk count)

    call new_suite(suite, "mpm_stencil")
    call check_stencils(linear, "linear", 2, 9000)
    call check_stencils(linear, "linear", 3, 5000)
    call check_stencils(gimp, "cpgimp", 2, 9000)
    call check_stencils(gimp, "cpgimp", 3, 5000)
    call check_stencils(gimp, "cpgimp", 2, 300)
    call check_stencils(ugimp, "ugimp", 2, 3000)
    call check_stencils(bspline2, "bspline2", 2, 9000)
    call check_stencils(bspline2, "bspline2", 3, 5000)
    call check_stencils(bspline3, "bspline3", 2, 9000)
    call check_stencils(bspline3, "bspline3", 3, 5000)
    call check_narrow_axis(gimp, "cpgimp")
    call check_narrow_axis(bspline3, "bspline3")
    call finish(suite)

contains

    !> A grid of the given dimension: 7 x 6 (x 5) cells of 0.1 m from (1, -2, 0.5).
    subroutine make_grid(grid, dim, ncells)
        type(grid_type), intent(out) :: grid
        integer, intent(in) :: dim
        integer, intent(in) :: ncells(3)
        call made_up_grid(grid, dim, ncells, 0.1_wp, [1.0_wp, -2.0_wp, 0.5_wp])
    end subroutine make_grid

    !> n particles spread over the grid (a quasi-random sweep), a tenth of them within half a
    !> cell of a domain face, each of half-size dx/4 (2 particles per cell).
    subroutine make_particles(particles, grid, n)
        type(particles_type), intent(out) :: particles
        type(grid_type), intent(in) :: grid
        integer, intent(in) :: n

        integer :: p, a, dim
        real(wp) :: t, extent, lp

        dim = grid%dim
        lp = 0.25_wp*grid%dx
        particles%n = n
        particles%dim = dim
        allocate (particles%x(dim, n), particles%lp0(dim, n), particles%f(dim, dim, n))
        do p = 1, n
            do a = 1, dim
                t = modulo(0.6180339887_wp*real(p, wp)*real(a + 1, wp) + 0.31_wp*a, 1.0_wp)
                extent = grid%dx*real(grid%ncells(a), wp) - 2.0_wp*lp
                if (mod(p, 10) == 0) then
                    ! next to the lower or upper face: the stencil is shifted inside
                    t = 0.5_wp*grid%dx*t/extent
                    if (mod(p, 20) == 0) t = 1.0_wp - t
                end if
                particles%x(a, p) = grid%origin(a) + lp + extent*t
            end do
            particles%lp0(:, p) = lp
            ! undeformed: the domain's half-sizes are lp0
            particles%f(:, :, p) = 0.0_wp
            do a = 1, dim
                particles%f(a, a, p) = 1.0_wp
            end do
        end do
    end subroutine make_particles

    !> Every property of the stencils of one shape function on one grid.
    subroutine check_stencils(shape, name, dim, n)
        class(shape_type), intent(in) :: shape
        character(len=*), intent(in) :: name
        integer, intent(in) :: dim, n

        type(grid_type) :: grid
        type(particles_type) :: particles
        type(stencils_type) :: stc
        type(error_type), allocatable :: error
        type(stencil_type) :: st
        character(len=:), allocatable :: what
        integer :: p, a, c, k, q, nps, lo, hi, layer, last_layer, last_p, expected, slow
        integer, allocatable :: node(:), seen(:)
        real(wp), allocatable :: w(:), dw(:, :)
        real(wp) :: xi, worst_pu, worst_axis_pu, worst_grad, worst_match
        logical :: first_ok, inside, match_nodes, ordered, stable, perm, chunks_ok, sizes_ok, &
            box_ok, layers_ok

        what = name//" "//dims(dim)//", "//int_str(n)//" particles: "
        call make_grid(grid, dim, [7, 6, 5])
        call make_particles(particles, grid, n)
        call compute_stencils(stc, grid, particles, shape, error)
        call check(suite, .not. allocated(error), what//"stencils computed")
        if (allocated(error)) return
        nps = shape%nodes_per_axis()
        slow = dim
        call check(suite, stc%nps == nps .and. stc%width == nps .and. &
            stc%count == nps**dim, what//"width and node count are the shape's")

        allocate (node(stc%count), w(stc%count), dw(3, stc%count))
        worst_pu = 0.0_wp
        worst_axis_pu = 0.0_wp
        worst_grad = 0.0_wp
        worst_match = 0.0_wp
        first_ok = .true.
        inside = .true.
        match_nodes = .true.
        do p = 1, n
            call particle_nodes(stc, p, node, w, dw)
            worst_pu = max(worst_pu, abs(sum(w) - 1.0_wp))
            worst_grad = max(worst_grad, maxval(abs(sum(dw(1:dim, :), dim=2)))*grid%dx)
            do a = 1, dim
                worst_axis_pu = max(worst_axis_pu, abs(sum(stc%w(:, a, p)) - 1.0_wp))
                ! kept nodes inside the grid
                if (stc%first(a, p) < 0 .or. stc%first(a, p) + nps - 1 > grid%nn(a) - 1) &
                    inside = .false.
                ! the shape's first node where no face shifts the stencil
                xi = (particles%x(a, p) - grid%origin(a))/grid%dx
                if (xi > 1.0_wp .and. xi < real(grid%ncells(a), wp) - 1.0_wp) then
                    if (nps == 2) then
                        if (stc%first(a, p) /= floor(xi)) first_ok = .false.
                    else if (nps == 4) then
                        if (stc%first(a, p) /= floor(xi) - 1) first_ok = .false.
                    else
                        if (stc%first(a, p) /= floor(xi - 0.5_wp)) first_ok = .false.
                    end if
                end if
            end do
            ! the same stencil from the shape function's tensor product (zero weights
            ! skipped there, kept here with zero gradients)
            call shape%evaluate(grid, particles%x(:, p), particles%lp0(:, p), st)
            do c = 1, stc%count
                k = findloc(st%node(1:st%count), node(c), dim=1)
                if (k == 0) then
                    if (w(c) > 0.0_wp .or. any(dw(1:dim, c) /= 0.0_wp)) match_nodes = .false.
                else
                    worst_match = max(worst_match, abs(w(c) - st%w(k)), &
                        maxval(abs(dw(1:dim, c) - st%dw(1:dim, k)))*grid%dx)
                end if
            end do
            if (count(w > 0.0_wp) /= st%count) match_nodes = .false.
        end do
        call check(suite, worst_pu <= round_off, what//"weights sum to one")
        call check(suite, worst_axis_pu <= round_off, what//"1D weights sum to one")
        call check(suite, worst_grad <= round_off, what//"gradients sum to zero")
        call check(suite, match_nodes .and. worst_match <= round_off, what//"nodes, weights "// &
            "and gradients are the shape function's")
        call check(suite, first_ok, what//"first node is the shape's")
        call check(suite, inside, what//"every kept node is inside the grid")

        ! the order: a permutation, by cell layer along the slowest axis, then by index
        allocate (seen(n))
        seen = 0
        perm = size(stc%order) == n
        ordered = .true.
        stable = .true.
        last_layer = -1
        last_p = 0
        do q = 1, n
            p = stc%order(q)
            if (p < 1 .or. p > n) then
                perm = .false.
                exit
            end if
            seen(p) = seen(p) + 1
            layer = min(max(int((particles%x(slow, p) - grid%origin(slow))/grid%dx), 0), &
                grid%ncells(slow) - 1)
            if (layer < last_layer) ordered = .false.
            if (layer == last_layer .and. p < last_p) stable = .false.
            last_layer = layer
            last_p = p
        end do
        perm = perm .and. all(seen == 1)
        call check(suite, perm, what//"order is a permutation of the particles")
        call check(suite, ordered, what//"particles ordered by cell layer (slowest axis)")
        call check(suite, stable, what//"within a layer by index")

        ! the chunks: equal parts of the order, their layers and the box hold their nodes
        expected = max(1, min(max_chunks, n/particles_per_chunk))
        sizes_ok = stc%nchunks == expected .and. stc%chunk_start(1) == 1 .and. &
            stc%chunk_start(stc%nchunks + 1) == n + 1
        chunks_ok = .true.
        layers_ok = .true.
        box_ok = .true.
        do k = 1, stc%nchunks
            c = stc%chunk_start(k + 1) - stc%chunk_start(k)
            if (abs(c - n/stc%nchunks) > 1) sizes_ok = .false.
            lo = huge(1)
            hi = -huge(1)
            do q = stc%chunk_start(k), stc%chunk_start(k + 1) - 1
                p = stc%order(q)
                lo = min(lo, stc%first(slow, p))
                hi = max(hi, stc%first(slow, p) + nps - 1)
                do a = 1, dim
                    if (stc%first(a, p) < stc%box_lo(a) .or. &
                        stc%first(a, p) + nps - 1 > stc%box_hi(a)) box_ok = .false.
                end do
            end do
            if (stc%chunk_lo(k) /= lo .or. stc%chunk_hi(k) /= hi) chunks_ok = .false.
            do layer = lo, hi
                if (k < stc%layer_chunks(1, layer) .or. k > stc%layer_chunks(2, layer)) &
                    layers_ok = .false.
            end do
        end do
        ! the box is tight: some particle touches each of its faces
        do a = 1, dim
            if (minval(stc%first(a, :)) /= stc%box_lo(a) .or. &
                maxval(stc%first(a, :)) + nps - 1 /= stc%box_hi(a)) box_ok = .false.
        end do
        call check(suite, sizes_ok, what//"chunks of equal size, as many as the count asks")
        call check(suite, chunks_ok, what//"node layers of each chunk are its particles'")
        call check(suite, layers_ok, what//"each layer lists the chunks that touch it")
        call check(suite, box_ok, what//"box of touched nodes is tight")
    end subroutine check_stencils

    !> An axis of one cell (2 nodes): cpGIMP keeps 2 of its 3 nodes there, the cubic spline 2
    !> of 4, so the stencils have no fast-path width (0) and the weights still sum to one.
    subroutine check_narrow_axis(shape, name)
        class(shape_type), intent(in) :: shape
            !! shape function
        character(len=*), intent(in) :: name
            !! its name
        type(grid_type) :: grid
        type(particles_type) :: particles
        type(stencils_type) :: stc
        type(error_type), allocatable :: error
        integer :: p
        integer, allocatable :: node(:)
        real(wp), allocatable :: w(:), dw(:, :)
        real(wp) :: worst

        call make_grid(grid, 2, [7, 1, 1])
        call make_particles(particles, grid, 200)
        call compute_stencils(stc, grid, particles, shape, error)
        call check(suite, .not. allocated(error), name//" narrow axis: stencils computed")
        if (allocated(error)) return
        call check(suite, stc%width == 0 .and. all(stc%nper(1:2) == [shape%nodes_per_axis(), 2]) &
            .and. stc%count == 2*shape%nodes_per_axis(), name//" narrow axis: no fast-path "// &
            "width, nps x 2 nodes")
        allocate (node(stc%count), w(stc%count), dw(3, stc%count))
        worst = 0.0_wp
        do p = 1, particles%n
            call particle_nodes(stc, p, node, w, dw)
            worst = max(worst, abs(sum(w) - 1.0_wp))
        end do
        call check(suite, worst <= round_off, name//" narrow axis: weights sum to one")
    end subroutine check_narrow_axis

    function int_str(i) result(text)
        integer, intent(in) :: i
        character(len=:), allocatable :: text
        character(len=12) :: buf
        write (buf, "(i0)") i
        text = trim(buf)
    end function int_str

end program test_mpm_stencil
