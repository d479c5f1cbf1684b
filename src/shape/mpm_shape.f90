!> Shape functions: the abstract interface every shape function extends, and the stencil of
!> one particle.
!>
!> A shape function is a tensor product of 1D weights. Each concrete shape function is an
!> extension of `shape_type` in its own module (linear, cpGIMP) and states:
!>
!> - its support width, `nodes_per_axis`: how many consecutive nodes per axis a particle
!>   can touch. The per-step stencils (mpm_stencil) and the transfer kernels are sized from
!>   it, and the kernels pick a variant with loops of constant length by this width;
!> - its halo width, `halo_width`: how many node layers two images must share at a cut of
!>   the grid (mpm_halo sums them after each scatter);
!> - its 1D weights and derivatives, `weights_1d`, which must sum to one (the stencils keep
!>   all derivatives but the last, which is minus the sum of the others);
!> - its names in the case file (`names`, `solver.shape_function`; the first is the one
!>   messages and the `--check` summary show);
!> - optionally, `initial_domain`: whether its weights take the particle domain at its
!>   initial size (`particles%lp0`, uGIMP) rather than the deformed one (`particles%lp`).
!>
!> `weights_all` evaluates `weights_1d` for every particle and axis once per step; a shape
!> function may override it with a loop that calls its own 1D weights directly (no dynamic
!> dispatch per particle, as linear and cpGIMP do). Evaluations are `pure` so they can run
!> inside threaded particle loops. mpm_shape_factory makes a shape function from its case
!> key.
module mpm_shape
    use mpm_kinds, only: wp
    use mpm_grid, only: grid_type
    implicit none
    private
    public :: shape_type, stencil_type, tensor_product, max_nodes_per_axis, max_stencil_nodes
    public :: shape_name_width, fold_ghost_nodes, full_shape_type

    integer, parameter :: max_nodes_per_axis = 4
        !! widest shape function the kernels take, in nodes per axis (4: a cubic B-spline);
        !! the factory refuses a wider one. Per-particle scratch has this fixed size: gfortran
        !! allocates an automatic array of run-time size on the heap, and per particle that
        !! cost 19 % of the default case in malloc and free
    integer, parameter :: max_stencil_nodes = max_nodes_per_axis**3
        !! most nodes of one particle's stencil (3D)
    integer, parameter :: shape_name_width = 24
        !! longest name of a shape function in the case file

    !> Nodes, weights and weight gradients of one particle (tests and diagnostics; the passes
    !> of a step use the 1D factors of mpm_stencil).
    type :: stencil_type
        integer :: count = 0
            !! number of nodes used
        integer, allocatable :: node(:)
            !! linear node indices (nodes_per_axis**dim entries, first count used)
        real(wp), allocatable :: w(:)
            !! weights N_i(x_p) [-]
        real(wp), allocatable :: dw(:, :)
            !! weight gradients dN_i/dx (3, nodes; first dim components used) [1/m]
    end type stencil_type

    !> A shape function: a tensor product of 1D weights.
    type, abstract :: shape_type
    contains
        procedure(weights_1d_interface), deferred :: weights_1d
            !! 1D weights and derivatives of the nodes around a coordinate
        procedure(width_interface), deferred :: nodes_per_axis
            !! support width: nodes per axis a particle can touch (2 linear, 3 cpGIMP)
        procedure(width_interface), deferred :: halo_width
            !! node layers two images share at a cut of the grid
        procedure(names_interface), deferred :: names
            !! its names in the case file (solver.shape_function), the one shown first
        procedure :: initial_domain
            !! whether the weights take the initial particle domain lp0 (default: no, lp)
        procedure :: weights_all
            !! weights_1d for every particle and axis (one call per step, threaded)
        procedure :: evaluate
            !! nodes, weights and gradients of one particle
    end type shape_type

    !> A shape function that is not a tensor product (CPDI: the weights of a particle follow
    !> its deformed domain, a parallelogram or parallelepiped, whose edges need not lie along
    !> the axes). Its stencil is still a box of nodes_per_axis nodes per axis, the box of the
    !> tensor shape functions, but it states a weight and a gradient for every node of the
    !> box (`weights_full`), from the particle's position, deformation gradient and initial
    !> domain; mpm_stencil keeps them and the kernels take them node by node. `weights_1d`
    !> gives its weights for a domain along the axes (F diagonal), which are then a tensor
    !> product: `evaluate` (tests and diagnostics) uses them.
    type, abstract, extends(shape_type) :: full_shape_type
    contains
        procedure(weights_full_interface), deferred :: weights_full
            !! the weights and gradients of every node of every particle's box
    end type full_shape_type

    abstract interface
        !> Weights and gradients of the nodes of each particle's box: nodes first(a, p) ..
        !> first(a, p) + nper(a) - 1 along axis a (0-based, inside the grid), x fastest.
        !> `bad` is the first particle whose weights do not fit in its box (its domain
        !> spans more nodes than nper along an axis), 0 when all fit.
        subroutine weights_full_interface(self, grid, x, f, lp0, nper, first, w, dw, bad)
            import :: full_shape_type, grid_type, wp
            class(full_shape_type), intent(in) :: self
                !! the shape function
            type(grid_type), intent(in) :: grid
                !! grid geometry
            real(wp), intent(in) :: x(:, :)
                !! particle positions (dim, n) [m]
            real(wp), intent(in) :: f(:, :, :)
                !! deformation gradients (dim, dim, n) [-]
            real(wp), intent(in) :: lp0(:, :)
                !! half-sizes of the initial domains (dim, n) [m]
            integer, intent(in) :: nper(3)
                !! nodes of the box per axis (1 on axis 3 in 2D)
            integer, intent(out) :: first(:, :)
                !! first node of the box per axis, 0-based (dim, n)
            real(wp), intent(out) :: w(:, :)
                !! weights (product(nper), n) [-]
            real(wp), intent(out) :: dw(:, :, :)
                !! gradients (dim, product(nper), n) [1/m]
            integer, intent(out) :: bad
                !! first particle whose domain does not fit its box, 0 if none
        end subroutine weights_full_interface
    end interface

    abstract interface
        !> 1D weights of the nodes first .. first + nodes_per_axis - 1 (0-based) around the
        !> coordinate xi (in cell units from the grid origin) of a particle of half-size lp.
        !> Nodes outside the grid may be named; their weights are zero. The weights sum to
        !> one. The arrays are contiguous, so an implementation passes them on to a routine
        !> of fixed width without a copy.
        pure subroutine weights_1d_interface(self, xi, lp, dx, ncells, first, w, dw)
            import :: shape_type, wp
            class(shape_type), intent(in) :: self
                !! the shape function
            real(wp), intent(in) :: xi
                !! particle coordinate in cell units, (x - origin) / dx [-]
            real(wp), intent(in) :: lp
                !! particle half-size [m]; unused by linear shape functions
            real(wp), intent(in) :: dx
                !! cell size [m]
            integer, intent(in) :: ncells
                !! cells along this axis
            integer, intent(out) :: first
                !! first node (0-based)
            real(wp), intent(out), contiguous :: w(:)
                !! weights of the nodes_per_axis nodes [-]
            real(wp), intent(out), contiguous :: dw(:)
                !! their derivatives with respect to the particle coordinate [1/m]
        end subroutine weights_1d_interface

        !> A width of the shape function, in nodes (nodes_per_axis, halo_width).
        pure integer function width_interface(self)
            import :: shape_type
            class(shape_type), intent(in) :: self
                !! the shape function
        end function width_interface

        !> The names of a shape function in the case file, any letter case (lower case here).
        pure subroutine names_interface(self, names)
            import :: shape_type, shape_name_width
            class(shape_type), intent(in) :: self
                !! the shape function
            character(len=shape_name_width), allocatable, intent(out) :: names(:)
                !! its names, the one messages show first
        end subroutine names_interface
    end interface

contains

    !> Whether the weights take the particle domain at its initial size (particles%lp0)
    !> instead of the deformed one (from F: domain_half_sizes): no, unless a shape function says so.
    pure logical function initial_domain(self)
        class(shape_type), intent(in) :: self
            !! the shape function
        initial_domain = .false.
    end function initial_domain

    !> weights_1d of the particles given along every axis of the grid: the generic loop (one
    !> dynamic call per particle and axis); a shape function may override it. Serial: the
    !> stencils call it for blocks of particles, on several threads
    !> (mpm_stencil::compute_stencils).
    subroutine weights_all(self, grid, x, lp, first, w, dw)
        class(shape_type), intent(in) :: self
            !! the shape function
        type(grid_type), intent(in) :: grid
            !! grid geometry
        real(wp), intent(in) :: x(:, :)
            !! particle positions (dim, n) [m]
        real(wp), intent(in) :: lp(:, :)
            !! particle half-sizes (dim, n) [m]
        integer, intent(out) :: first(:, :)
            !! first node per axis, 0-based (dim, n)
        real(wp), intent(out) :: w(:, :, :)
            !! weights (nodes_per_axis, dim, n) [-]
        real(wp), intent(out) :: dw(:, :, :)
            !! derivatives of the first nodes_per_axis - 1 nodes (nodes_per_axis - 1, dim,
            !! n) [1/m]; the last one is minus their sum (the weights sum to one), so it
            !! is not stored

        integer :: p, a, nps
        real(wp) :: xi, w1(size(w, 1)), dw1(size(w, 1))

        nps = size(w, 1)
        do p = 1, size(x, 2)
            do a = 1, grid%dim
                xi = (x(a, p) - grid%origin(a))/grid%dx
                call self%weights_1d(xi, lp(a, p), grid%dx, grid%ncells(a), first(a, p), w1, dw1)
                w(:, a, p) = w1
                dw(:, a, p) = dw1(1:nps - 1)
            end do
        end do
    end subroutine weights_all

    !> The boundary modification of a spline basis: the weight of a node one beyond a grid
    !> end (node -1 or ncells + 1, outside the grid) is given to the two nodes inside it,
    !> twice to the end node and minus once to the next, N_0 += 2 N_-1, N_1 -= N_-1 (and
    !> likewise at the upper end). The basis keeps the partition of unity, reproduces linear
    !> functions up to the grid ends (the ghost node's value extrapolated linearly from the
    !> two inside, u_-1 = 2 u_0 - u_1), keeps the smoothness of the spline (a sum of the same
    !> splines) and stays non-negative: quadratic splines become N_0 = 1 - x, N_1 = x within
    !> half a cell of the end (x in cells from it), a boundary modification in the sense of
    !> Steffen, Kirby and Berzins (2008) (not compared term by term with their formulas),
    !> and cubic ones N_0 = 1 - x + x**3/6 within a cell. Weights and derivatives of the
    !> ghost nodes become zero.
    pure subroutine fold_ghost_nodes(first, ncells, w, dw)
        integer, intent(in) :: first
            !! node (0-based) of w(1)
        integer, intent(in) :: ncells
            !! cells along the axis (nodes 0 .. ncells)
        real(wp), intent(inout) :: w(:)
            !! weights of nodes first .. first + size(w) - 1 [-]
        real(wp), intent(inout) :: dw(:)
            !! their derivatives [1/m]

        integer :: k, j, n

        n = size(w)
        do k = 1, n
            j = first + k - 1
            if (j == -1 .and. k + 2 <= n) then
                w(k + 1) = w(k + 1) + 2.0_wp*w(k)
                w(k + 2) = w(k + 2) - w(k)
                dw(k + 1) = dw(k + 1) + 2.0_wp*dw(k)
                dw(k + 2) = dw(k + 2) - dw(k)
                w(k) = 0.0_wp
                dw(k) = 0.0_wp
            else if (j == ncells + 1 .and. k - 2 >= 1) then
                w(k - 1) = w(k - 1) + 2.0_wp*w(k)
                w(k - 2) = w(k - 2) - w(k)
                dw(k - 1) = dw(k - 1) + 2.0_wp*dw(k)
                dw(k - 2) = dw(k - 2) - dw(k)
                w(k) = 0.0_wp
                dw(k) = 0.0_wp
            end if
        end do
    end subroutine fold_ghost_nodes

    !> Stencil of a particle at `xp` with GIMP half-sizes `lp`: the tensor product of the
    !> 1D weights, nodes outside the grid and zero weights skipped.
    pure subroutine evaluate(self, grid, xp, lp, st)
        class(shape_type), intent(in) :: self
            !! the shape function
        type(grid_type), intent(in) :: grid
            !! grid geometry (nn, dx, origin)
        real(wp), intent(in) :: xp(:)
            !! particle position (dim) [m]
        real(wp), intent(in) :: lp(:)
            !! particle half-sizes (dim) [m]; unused by linear shape functions
        type(stencil_type), intent(out) :: st
            !! nodes, weights, gradients

        integer :: a, first(3)
        real(wp), allocatable :: w1(:, :), dw1(:, :)

        allocate (w1(self%nodes_per_axis(), 3), dw1(self%nodes_per_axis(), 3))
        first = 0
        w1 = 0.0_wp
        dw1 = 0.0_wp
        w1(1, 3) = 1.0_wp
        do a = 1, grid%dim
            call self%weights_1d((xp(a) - grid%origin(a))/grid%dx, lp(a), grid%dx, &
                grid%ncells(a), first(a), w1(:, a), dw1(:, a))
        end do
        call tensor_product(grid, first, w1, dw1, st)
    end subroutine evaluate

    !> Tensor-product stencil from per-axis weights.
    !>
    !> Axis `a` uses nodes first(a) .. first(a) + nper - 1 (0-based, nper = size(w1, 1)) with
    !> weights w1(:, a) and derivatives dw1(:, a). Nodes outside the grid and zero weights are
    !> skipped.
    pure subroutine tensor_product(grid, first, w1, dw1, st)
        type(grid_type), intent(in) :: grid
            !! grid geometry
        integer, intent(in) :: first(3)
            !! first node along each axis (0-based)
        real(wp), intent(in) :: w1(:, :)
            !! 1D weights (node, axis) [-]
        real(wp), intent(in) :: dw1(:, :)
            !! 1D weight derivatives (node, axis) [1/m]
        type(stencil_type), intent(out) :: st
            !! resulting stencil

        integer :: i, j, k, ii, jj, kk, nk, c, nper
        real(wp) :: wij

        nper = size(w1, 1)
        c = 0
        if (grid%dim == 2) then
            nk = 1
        else
            nk = nper
        end if
        allocate (st%node(nper*nper*nk), st%w(nper*nper*nk), st%dw(3, nper*nper*nk))
        st%node = 0
        st%w = 0.0_wp
        st%dw = 0.0_wp
        do k = 1, nk
            kk = first(3) + k - 1
            if (kk < 0 .or. kk >= grid%nn(3)) cycle
            do j = 1, nper
                jj = first(2) + j - 1
                if (jj < 0 .or. jj >= grid%nn(2)) cycle
                do i = 1, nper
                    ii = first(1) + i - 1
                    if (ii < 0 .or. ii >= grid%nn(1)) cycle
                    if (grid%dim == 2) then
                        wij = w1(i, 1)*w1(j, 2)
                        if (wij <= 0.0_wp) cycle
                        c = c + 1
                        st%w(c) = wij
                        st%dw(1, c) = dw1(i, 1)*w1(j, 2)
                        st%dw(2, c) = w1(i, 1)*dw1(j, 2)
                        st%dw(3, c) = 0.0_wp
                    else
                        wij = w1(i, 1)*w1(j, 2)*w1(k, 3)
                        if (wij <= 0.0_wp) cycle
                        c = c + 1
                        st%w(c) = wij
                        st%dw(1, c) = dw1(i, 1)*w1(j, 2)*w1(k, 3)
                        st%dw(2, c) = w1(i, 1)*dw1(j, 2)*w1(k, 3)
                        st%dw(3, c) = w1(i, 1)*w1(j, 2)*dw1(k, 3)
                    end if
                    st%node(c) = 1 + ii + grid%nn(1)*(jj + grid%nn(2)*kk)
                end do
            end do
        end do
        st%count = c
    end subroutine tensor_product

end module mpm_shape
