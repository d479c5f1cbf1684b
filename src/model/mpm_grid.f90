!> The background grid: a regular Cartesian grid of nodes with nodal fields.
!>
!> Nodes are numbered lexicographically, x fastest: node (i, j, k) (0-based) has the index
!> 1 + i + nn(1) * (j + nn(2) * k). In 2D nn(3) = 1 and k = 0.
module mpm_grid
    use, intrinsic :: iso_c_binding, only: c_f_pointer, c_loc
    use, intrinsic :: iso_fortran_env, only: int64
    use mpm_kinds, only: wp
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_case, only: case_type
    use mpm_boundary, only: face_nodes_type
    use mpm_terrain, only: terrain_type, new_terrain, terrain_distance
    implicit none
    private
    public :: fold_periodic, slave_periodic
    public :: grid_type, new_grid, add_terrain, node_index, node_position, contact_index, &
        grid_bytes, node_owned, &
        node_layer

    integer, parameter :: page_entries = 512
        !! entries of a block that new_grid zeroes as a whole (a 4 KiB page of reals)

    !> Geometry of the grid and the nodal fields of one step.
    type :: grid_type
        integer :: dim = 2
            !! space dimensions
        integer :: ncells(3) = 1
            !! cells per direction (1 in z for 2D)
        integer :: nn(3) = 1
            !! nodes per direction (ncells + 1; 1 in z for 2D)
        integer :: nnodes = 0
            !! total number of nodes
        real(wp) :: dx = 0.0_wp
            !! cell size [m]
        real(wp) :: origin(3) = 0.0_wp
            !! position of node (0, 0, 0) [m]
        logical :: clamped(2, 3) = .false.
            !! a particle moved past the face (side, axis) is put back on it: the face is a
            !! wall (its condition's keeps_particles)
        logical :: periodic(3) = .false.
            !! the two faces of the axis are tied (periodic): a particle leaving through one
            !! comes back through the other
        integer :: nperiodic = 0
            !! pairs of tied nodes (a node on two periodic axes, an edge, is tied once per
            !! axis, in axis order, to the node of the lowest faces)
        integer, allocatable :: periodic_slave(:), periodic_master(:)
            !! each pair's node on the upper face and its node on the lower face (nperiodic)
        real(wp), allocatable :: mass(:)
            !! nodal mass (nnodes) [kg]
        real(wp), allocatable :: momentum(:, :)
            !! nodal momentum (dim, nnodes) [kg m/s]
        real(wp), allocatable :: fint(:, :)
            !! internal force (dim, nnodes) [N]
        real(wp), allocatable :: fext(:, :)
            !! external (body) force (dim, nnodes) [N]
        real(wp), allocatable :: velocity(:, :)
            !! nodal velocity after the update (dim, nnodes) [m/s]
        real(wp), allocatable :: acceleration(:, :)
            !! nodal acceleration of the step (dim, nnodes) [m/s2]
        real(wp), allocatable :: xpic(:, :)
            !! with solver.transfer = "xpic": the filtered start velocity of the step that G2P
            !! gives the particles with the step's accelerations (dim, nnodes) [m/s]
        real(wp), allocatable :: scratch(:)
            !! buffers of the scatter passes (mpm_transfer), kept from step to step: a fresh
            !! allocation per pass costs page faults and the zeroing of new pages
        logical, allocatable :: constrained(:, :)
            !! velocity component held at zero by a boundary condition (dim, nnodes)
        integer :: nprescribed = 0
            !! number of (node, velocity face) pairs: nodes whose velocity a face prescribes
        integer, allocatable :: prescribed_node(:)
            !! node of each pair (nprescribed)
        integer, allocatable :: prescribed_face(:, :)
            !! face (side, axis) of each pair (2, nprescribed)
        real(wp), allocatable :: prescribed_velocity(:, :)
            !! velocity the face gives the node (dim, nprescribed) [m/s]
        logical, allocatable :: prescribed_mask(:, :)
            !! the components whose reaction the pair's face books: those no face before it
            !! holds (a corner's component goes to one face) (dim, nprescribed)
        logical, allocatable :: prescribed_last(:)
            !! the pair is the last of its node (the face whose velocity set_prescribed leaves
            !! it with) (nprescribed)
        logical :: prescribed_varies = .false.
            !! a velocity face's velocity changes in time (a seismic base): the solver sets
            !! prescribed_start and prescribed_velocity each step (face_varies)
        logical :: face_varies(2, 3) = .false.
            !! whether the prescribed velocity of face (side, axis) changes in time
        real(wp), allocatable :: prescribed_start(:, :)
            !! with prescribed_varies: the velocity the face gave the node at the start of the
            !! step (dim, nprescribed) [m/s]
        integer :: nheld = 0
            !! number of (node, holding face) pairs: nodes of the faces that hold components
            !! at zero (sliding, fixed), for their reactions
        integer, allocatable :: held_node(:)
            !! node of each pair (nheld)
        integer, allocatable :: held_face(:, :)
            !! face (side, axis) of each pair (2, nheld)
        logical, allocatable :: held_mask(:, :)
            !! the components whose reaction the pair's face books: those it holds that no
            !! face before it holds (a corner's component goes to one face) (dim, nheld)
        integer :: nregion_nodes = 0
            !! number of nodes moved by the regions of prescribed_motion in this step
            !! (mpm_motion marks them at the start of each step and releases them at its end)
        integer, allocatable :: region_node(:)
            !! node of each (nregion_nodes)
        integer, allocatable :: region_of(:)
            !! the region that moves it (nregion_nodes)
        logical, allocatable :: region_saved(:, :)
            !! its constrained components before the region held them (dim, nregion_nodes)
        real(wp), allocatable :: region_velocity(:, :)
            !! velocity of each region in this step (dim, regions) [m/s]
        logical, allocatable :: region_held(:, :)
            !! the components each region holds (dim, regions)
        real(wp), allocatable :: region_impulse(:, :)
            !! impulse each region gave the material in the last nodal update, over this
            !! image's nodes (node_owned) (dim, regions) [N s]
        integer, allocatable :: region_rigid(:)
            !! the rigid material of each region that is a rigid body, 0 for a box (regions)
        integer, allocatable :: region_mark(:)
            !! the region that moves each node in this step, 0 for none (nodes; kept zero
            !! between the steps)
        real(wp), allocatable :: body_velocity(:, :)
            !! velocity of each rigid body at the end of the step's nodal update (dim,
            !! regions; zero for a box) [m/s]
        real(wp), allocatable :: body_fill(:)
            !! scratch of mpm_motion::hold_regions: the volume of a rigid body's particles
            !! weighted by each node's shape function (nodes; kept zero between the steps)
            !! [m3, m2 in 2D]
        real(wp), allocatable :: body_start(:, :)
            !! displacement of each rigid body at the step's start, the mean of its particles'
            !! by mass (dim, regions; zero for a box) [m]
        logical :: keep_reaction = .false.
            !! keep the force of the constraints on each node (output.grid)
        real(wp), allocatable :: node_reaction(:, :)
            !! force the faces, the regions of prescribed_motion and the rigid bodies applied
            !! on each node over the last nodal update, the node's share of their reactions
            !! (dim, nnodes; zero elsewhere; only with keep_reaction) [N, N/m in 2D]
        logical :: bodies_moved = .false.
            !! whether the nodal update of this step has set body_velocity
        integer :: nacting = 0
            !! number of (node, acting face) pairs: nodes of faces whose condition acts on
            !! them after each nodal update (an absorbing face)
        integer, allocatable :: acting_node(:)
            !! node of each pair, face by face (nacting)
        integer, allocatable :: acting_face(:, :)
            !! face (side, axis) of each pair (2, nacting)
        real(wp), allocatable :: acting_disp(:, :)
            !! displacement of each pair's node since the start, kept by the conditions with
            !! springs (a Kelvin-Voigt face) (dim, nacting) [m]
        real(wp), allocatable :: acting_area(:)
            !! the face area each pair's node stands for: dx^(dim - 1), halved per edge of
            !! the face it lies on (not across a periodic axis) (nacting) [m2; m in 2D]
        real(wp) :: face_impulse(3, 2, 3) = 0.0_wp
            !! impulse each face (side, axis) gave the material in the last nodal update, over
            !! this image's nodes (node_owned): the velocity faces' and the holding faces' (the
            !! force on their held components); zero at the others [N s]
        integer :: ncontacts = 0
            !! number of (node, frictional face) pairs
        integer, allocatable :: contact_node(:)
            !! node of each pair (ncontacts)
        integer, allocatable :: contact_axis(:)
            !! axis normal to the face of each pair (ncontacts)
        real(wp), allocatable :: contact_normal(:)
            !! outward normal of the face along contact_axis: -1 (min face) or +1 (ncontacts)
        real(wp), allocatable :: contact_dir(:, :)
            !! unit normal of each pair into the obstacle (dim, ncontacts): a face's outward
            !! normal
        real(wp), allocatable :: contact_mu(:)
            !! Coulomb friction coefficient of the face (ncontacts) [-]
        real(wp), allocatable :: contact_gap(:)
            !! gap between the material and the face at each pair, set by P2G (ncontacts) [m]
        real(wp), allocatable :: contact_load(:)
            !! running mean of the normal impulse the face takes at each pair (ncontacts) [N s]
        real(wp), allocatable :: contact_friction(:, :)
            !! friction impulse of the last nodal update at each pair (dim, ncontacts) [N s]
        real(wp), allocatable :: contact_impulse(:, :)
            !! the part of the normal constraint's impulse in the last nodal update at each
            !! pair that stopped the normal velocity the node brought into the step (not the
            !! one the step's forces added), - m v_s n (dim, ncontacts) [N s]
        real(wp), allocatable :: contact_start(:, :)
            !! momentum P2G gave the node of each pair at the start of the step, before any
            !! constraint (dim, ncontacts) [kg m/s]
        integer :: contact_offset(2, 3) = -1
            !! index before the first pair of each face (side, axis); -1: face not frictional
        real(wp) :: small_mass = 0.0_wp
            !! nodes of this mass or less are empty: at rest, no force, no momentum (round-off
            !! level, set by the solver from the lightest particle) [kg]
        real(wp) :: light_mass = 0.0_wp
            !! nodes of this mass or less with a heavier neighbour are slaved to their heavy
            !! neighbours in each step (mpm_kernel_light) [kg]; 0: none
        integer :: nlight = 0
            !! number of light nodes of the step (on a cut grid: those this image treats)
        integer :: light_layers = 0
            !! node layers shared at a cut when the light nodes were found (their folds and
            !! slaved values are traded over them)
        integer, allocatable :: light_node(:)
            !! the light nodes of the step (nlight used)
        integer, allocatable :: light_start(:)
            !! first entry of each light node in light_master and light_coef (nlight + 1 used)
        integer, allocatable :: light_master(:)
            !! heavy neighbours (masters) of the light nodes
        real(wp), allocatable :: light_coef(:)
            !! share of each master, m_j / sum_k m_k over the masters of its light node [-]
        real(wp) :: contact_time = 0.0_wp
            !! time constant of the running mean of the normal contact impulse [s]; 0: a fixed
            !! weight per step
        integer :: active_lo(3) = 0, active_hi(3) = huge(1)/2
            !! the box of nodes (0-based, per axis) that the last P2G wrote (every other node
            !! is zero): empty (lo > hi) in a grid new_grid has just made, the whole grid in one
            !! made otherwise; the nodal loops of the step cover it
        integer :: halo_axis = 0
            !! axis across which the grid is cut among images (mpm_decomposition); 0: whole
        integer :: halo_left = 0, halo_right = 0
            !! neighbouring images on the low and high side of halo_axis, 0 for none; the
            !! three node layers at each end with a neighbour are shared with it
        integer :: owned_lo = 0, owned_hi = huge(1)/2
            !! node layers along halo_axis (0-based) whose energies this image counts (every
            !! node is counted by one image)
        type(terrain_type), allocatable :: terrain
            !! rigid terrain surface (contact.type = "terrain_stl"), absent otherwise
        integer, allocatable :: terrain_pair(:)
            !! contact pair of each node with the terrain, 0 for none (nnodes; with terrain)
    end type grid_type

contains

    !> Index (0-based) along axis a of node id.
    pure integer function node_layer(grid, id, a)
        type(grid_type), intent(in) :: grid
            !! the grid
        integer, intent(in) :: id
            !! node index
        integer, intent(in) :: a
            !! axis

        select case (a)
        case (1)
            node_layer = mod(id - 1, grid%nn(1))
        case (2)
            node_layer = mod((id - 1)/grid%nn(1), grid%nn(2))
        case default
            node_layer = (id - 1)/(grid%nn(1)*grid%nn(2))
        end select
    end function node_layer

    !> Whether this image counts node id in the energy sums (always, when the grid is whole).
    pure logical function node_owned(grid, id)
        type(grid_type), intent(in) :: grid
            !! the grid
        integer, intent(in) :: id
            !! node index

        integer :: layer

        node_owned = .true.
        if (grid%halo_axis == 0) return
        layer = node_layer(grid, id, grid%halo_axis)
        node_owned = layer >= grid%owned_lo .and. layer <= grid%owned_hi
    end function node_owned

    !> Build the grid of a case, with its boundary constraints.
    subroutine new_grid(grid, case, error)
        type(grid_type), intent(out) :: grid
            !! grid to create
        type(case_type), intent(in) :: case
            !! resolved case
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        integer :: stat, i, j, k, a, id, d, side, face, c, n, m, h, lo(3), hi(3)
        logical :: before(3)
        character(len=256) :: msg
        type(face_nodes_type) :: nodes(2, 3)

        grid%dim = case%dim
        grid%ncells = 1
        grid%ncells(1:case%dim) = case%domain%ncells(1:case%dim)
        grid%nn = 1
        grid%nn(1:case%dim) = grid%ncells(1:case%dim) + 1
        grid%nnodes = product(grid%nn)
        grid%dx = case%domain%dx
        grid%origin = case%domain%origin
        d = case%dim
        do a = 1, d
            do side = 1, 2
                nodes(side, a) = case%domain%nodes(side, a, d)
                grid%clamped(side, a) = nodes(side, a)%keeps_particles
            end do
            grid%periodic(a) = nodes(1, a)%periodic .and. nodes(2, a)%periodic
        end do
        call periodic_pairs(grid)
        allocate (grid%mass(grid%nnodes), grid%momentum(d, grid%nnodes), &
            grid%fint(d, grid%nnodes), grid%fext(d, grid%nnodes), &
            grid%velocity(d, grid%nnodes), grid%acceleration(d, grid%nnodes), &
            grid%constrained(d, grid%nnodes), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the grid: "//trim(msg), exit_other)
            return
        end if
        ! zero, writing only pages that are not zero yet: a large allocation comes from the
        ! system as pages of zeros that take memory once written, and the nodal passes write
        ! only the box of nodes the particles touch, so that the nodes far from the material
        ! cost no memory (a small slide in a large domain)
        call clear_reals(grid%mass)
        call clear_vectors(grid%momentum)
        call clear_vectors(grid%fint)
        call clear_vectors(grid%fext)
        call clear_vectors(grid%velocity)
        call clear_vectors(grid%acceleration)
        call clear_logicals(grid%constrained)
        ! no node holds anything yet: the first P2G writes only the box its particles touch
        grid%active_lo = huge(1)/2
        grid%active_hi = -1
        ! each face's condition holds velocity components of its nodes (sliding: the normal
        ! one, fixed: all; velocity: all, at its velocity) or makes them contact pairs, applied
        ! during the nodal update (frictional: contact with friction, lift-off allowed)
        grid%ncontacts = 0
        grid%nprescribed = 0
        grid%nacting = 0
        grid%face_varies = .false.
        do a = 1, d
            do side = 1, 2
                grid%face_varies(side, a) = nodes(side, a)%prescribed .and. nodes(side, a)%varies
                if (nodes(side, a)%contact) grid%ncontacts = grid%ncontacts &
                    + grid%nnodes/grid%nn(a)
                if (nodes(side, a)%prescribed) grid%nprescribed = grid%nprescribed &
                    + grid%nnodes/grid%nn(a)
                if (nodes(side, a)%acts) grid%nacting = grid%nacting + grid%nnodes/grid%nn(a)
                if (holds(nodes(side, a))) grid%nheld = grid%nheld + grid%nnodes/grid%nn(a)
            end do
        end do
        allocate (grid%prescribed_node(grid%nprescribed), &
            grid%prescribed_face(2, grid%nprescribed), &
            grid%acting_node(grid%nacting), grid%acting_face(2, grid%nacting), &
            grid%acting_disp(d, grid%nacting), grid%acting_area(grid%nacting), &
            grid%held_node(grid%nheld), grid%held_face(2, grid%nheld), &
            grid%held_mask(d, grid%nheld), &
            grid%prescribed_velocity(d, grid%nprescribed), &
            grid%prescribed_mask(d, grid%nprescribed), &
            grid%contact_node(grid%ncontacts), grid%contact_axis(grid%ncontacts), &
            grid%contact_normal(grid%ncontacts), grid%contact_dir(d, grid%ncontacts), &
            grid%contact_mu(grid%ncontacts), &
            grid%contact_gap(grid%ncontacts), grid%contact_load(grid%ncontacts), &
            grid%contact_friction(d, grid%ncontacts), grid%contact_impulse(d, grid%ncontacts), &
            grid%contact_start(d, grid%ncontacts), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the grid: "//trim(msg), exit_other)
            return
        end if
        allocate (grid%prescribed_last(grid%nprescribed), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the grid: "//trim(msg), exit_other)
            return
        end if
        grid%prescribed_varies = any(grid%face_varies)
        if (grid%prescribed_varies) then
            allocate (grid%prescribed_start(d, grid%nprescribed), stat=stat, errmsg=msg)
            if (stat /= 0) then
                call fatal_error(error, "cannot allocate the grid: "//trim(msg), exit_other)
                return
            end if
        end if
        grid%contact_load = 0.0_wp
        grid%acting_disp = 0.0_wp
        grid%contact_friction = 0.0_wp
        grid%contact_impulse = 0.0_wp
        grid%contact_start = 0.0_wp
        grid%contact_gap = huge(1.0_wp)
        c = 0
        n = 0
        m = 0
        h = 0
        do a = 1, d
            do side = 1, 2
                face = merge(0, grid%nn(a) - 1, side == 1)
                if (nodes(side, a)%contact) grid%contact_offset(side, a) = c
                lo = 0
                hi = grid%nn - 1
                lo(a) = face
                hi(a) = face
                do k = lo(3), hi(3)
                    do j = lo(2), hi(2)
                        do i = lo(1), hi(1)
                            id = node_index(grid, [i, j, k])
                            before(1:d) = grid%constrained(:, id)
                            if (holds(nodes(side, a))) then
                                h = h + 1
                                grid%held_node(h) = id
                                grid%held_face(:, h) = [side, a]
                                grid%held_mask(:, h) = nodes(side, a)%held(1:d) &
                                    .and. .not. before(1:d)
                            end if
                            grid%constrained(:, id) = grid%constrained(:, id) &
                                .or. nodes(side, a)%held(1:d)
                            if (nodes(side, a)%prescribed) then
                                n = n + 1
                                grid%prescribed_node(n) = id
                                grid%prescribed_face(:, n) = [side, a]
                                grid%prescribed_velocity(:, n) = nodes(side, a)%velocity(1:d)
                                if (grid%prescribed_varies) grid%prescribed_start(:, n) = &
                                    nodes(side, a)%velocity(1:d)
                                grid%prescribed_last(n) = .not. later_prescribed([i, j, k], a)
                                grid%prescribed_mask(:, n) = .not. before(1:d)
                            end if
                            if (nodes(side, a)%acts) then
                                m = m + 1
                                grid%acting_node(m) = id
                                grid%acting_face(:, m) = [side, a]
                                grid%acting_area(m) = face_area([i, j, k], a)
                            end if
                            if (nodes(side, a)%contact) then
                                c = c + 1
                                grid%contact_node(c) = id
                                grid%contact_axis(c) = a
                                grid%contact_normal(c) = merge(-1.0_wp, 1.0_wp, side == 1)
                                grid%contact_dir(:, c) = 0.0_wp
                                grid%contact_dir(a, c) = grid%contact_normal(c)
                                grid%contact_mu(c) = nodes(side, a)%mu
                            end if
                        end do
                    end do
                end do
            end do
        end do

    contains

        !> Whether a face after the faces of axis `a` (in the order of the loop) prescribes
        !> the velocity of the node at ijk too (an edge or corner of two velocity faces).
        pure logical function later_prescribed(ijk, a)
            integer, intent(in) :: ijk(3), a

            integer :: a2, s2

            later_prescribed = .false.
            do a2 = a + 1, d
                do s2 = 1, 2
                    if (.not. nodes(s2, a2)%prescribed) cycle
                    if (ijk(a2) == merge(0, grid%nn(a2) - 1, s2 == 1)) later_prescribed = .true.
                end do
            end do
        end function later_prescribed

        !> The face area of node ijk of a face normal to axis a: dx^(d - 1), halved for each
        !> other axis on whose first or last node it lies (unless that axis is periodic, whose
        !> lower node stands for both).
        pure real(wp) function face_area(ijk, a)
            integer, intent(in) :: ijk(3), a

            integer :: b

            face_area = grid%dx**(d - 1)
            do b = 1, d
                if (b == a .or. grid%periodic(b)) cycle
                if (ijk(b) == 0 .or. ijk(b) == grid%nn(b) - 1) face_area = 0.5_wp*face_area
            end do
        end function face_area

        !> A face whose nodes hold components at zero (not a velocity face, which books its
        !> reaction as prescribed).
        pure logical function holds(face_nodes)
            type(face_nodes_type), intent(in) :: face_nodes

            holds = any(face_nodes%held(1:d)) .and. .not. face_nodes%prescribed
        end function holds

    end subroutine new_grid

    !> The pairs of tied nodes of the periodic axes: each node of an upper face with the
    !> node of the lower face across, axis by axis (an edge node of two periodic axes is
    !> tied along the first to a node that the second then ties: folds in pair order reach
    !> the corner of the lowest faces, and copies in reverse order come back).
    pure subroutine periodic_pairs(grid)
        type(grid_type), intent(inout) :: grid
            !! the grid (nn, periodic set)

        integer :: a, i, j, k, n, ijk(3), stride(3)

        stride = [1, grid%nn(1), grid%nn(1)*grid%nn(2)]
        n = 0
        do a = 1, grid%dim
            if (grid%periodic(a)) n = n + grid%nnodes/grid%nn(a)
        end do
        grid%nperiodic = n
        allocate (grid%periodic_slave(n), grid%periodic_master(n))
        n = 0
        do a = 1, grid%dim
            if (.not. grid%periodic(a)) cycle
            do k = 0, grid%nn(3) - 1
                do j = 0, grid%nn(2) - 1
                    do i = 0, grid%nn(1) - 1
                        ijk = [i, j, k]
                        if (ijk(a) /= grid%nn(a) - 1) cycle
                        n = n + 1
                        grid%periodic_slave(n) = 1 + dot_product(ijk, stride)
                        ijk(a) = 0
                        grid%periodic_master(n) = 1 + dot_product(ijk, stride)
                    end do
                end do
            end do
        end do
    end subroutine periodic_pairs

    !> The sums of the tied nodes of periodic faces on the lower face's nodes: each pair's
    !> upper node gives its mass, momentum and forces to its lower node and keeps none
    !> (after every scatter; nothing without periodic faces).
    pure subroutine fold_periodic(grid)
        type(grid_type), intent(inout) :: grid
            !! the grid after a scatter

        integer :: n, s, m

        do n = 1, grid%nperiodic
            s = grid%periodic_slave(n)
            m = grid%periodic_master(n)
            grid%mass(m) = grid%mass(m) + grid%mass(s)
            grid%momentum(:, m) = grid%momentum(:, m) + grid%momentum(:, s)
            grid%fint(:, m) = grid%fint(:, m) + grid%fint(:, s)
            grid%fext(:, m) = grid%fext(:, m) + grid%fext(:, s)
            grid%mass(s) = 0.0_wp
            grid%momentum(:, s) = 0.0_wp
            grid%fint(:, s) = 0.0_wp
            grid%fext(:, s) = 0.0_wp
        end do
    end subroutine fold_periodic

    !> The upper nodes of periodic faces at the velocity and acceleration of their lower
    !> nodes (after every nodal update), in the reverse order of the folds.
    pure subroutine slave_periodic(grid)
        type(grid_type), intent(inout) :: grid
            !! the grid after a nodal update

        integer :: n

        do n = grid%nperiodic, 1, -1
            grid%velocity(:, grid%periodic_slave(n)) = grid%velocity(:, grid%periodic_master(n))
            grid%acceleration(:, grid%periodic_slave(n)) = &
                grid%acceleration(:, grid%periodic_master(n))
        end do
    end subroutine slave_periodic

    !> Frictional contact with a rigid terrain surface: every node within two cells of the
    !> surface becomes a contact pair (after the pairs of the frictional faces) whose normal
    !> is that of the nearest triangle, into the terrain; P2G sets its gap from the particles
    !> and the nodal update applies it like a frictional face.
    !>
    !> On one image's slab (`offset`), the node positions are those of the whole grid
    !> (`global_origin` + dx (ijk + offset)), so that two images sharing a node give it the
    !> same pair, normal and bits; `allow_empty` then accepts a surface that misses the slab.
    subroutine add_terrain(grid, corner, mu, gravity, error, global_origin, offset, allow_empty)
        type(grid_type), intent(inout) :: grid
            !! grid made by new_grid
        real(wp), intent(in) :: corner(:, :, :)
            !! (3, 3, n) triangle corners of the surface [m]
        real(wp), intent(in) :: mu
            !! Coulomb friction coefficient [-]
        real(wp), intent(in) :: gravity(3)
            !! gravity: the material is on the surface's side against it [m/s2]
        type(error_type), allocatable, intent(out) :: error
            !! set when the surface misses the grid or memory cannot be allocated
        real(wp), intent(in), optional :: global_origin(3)
            !! origin of the whole grid (default: this grid's) [m]
        integer, intent(in), optional :: offset(3)
            !! node coordinates of this grid's node (0, 0, 0) in the whole grid (default 0)
        logical, intent(in), optional :: allow_empty
            !! no error when the surface misses this grid (one image's slab)

        integer :: id, c, nold, nnew, stat, d, box(3), shift(3)
        real(wp) :: x(3), dist, n(3), base(3)
        logical :: found
        integer, allocatable :: node(:), axis(:)
        real(wp), allocatable :: normal(:), dir(:, :), friction(:), gap(:), load(:), &
            impulse(:, :)
        character(len=256) :: msg

        d = grid%dim
        base = grid%origin
        if (present(global_origin)) base = global_origin
        shift = 0
        if (present(offset)) shift = offset
        ! the index covers the cells and one more layer at the upper ends, so that the last
        ! nodes (on the upper faces of the box) are inside it too
        box = grid%ncells
        box(1:d) = box(1:d) + 1
        allocate (grid%terrain)
        call new_terrain(grid%terrain, corner, grid%origin, box, grid%dx, d, &
            2.0_wp*grid%dx, gravity, error, allow_empty)
        if (allocated(error)) return
        allocate (grid%terrain_pair(grid%nnodes), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the terrain contacts: "//trim(msg), &
                exit_other)
            return
        end if
        grid%terrain_pair = 0
        nnew = 0
        do id = 1, grid%nnodes
            x = terrain_node_position(id)
            call terrain_distance(grid%terrain, x, found, dist, n)
            if (found) nnew = nnew + 1
        end do
        nold = grid%ncontacts
        allocate (node(nold + nnew), axis(nold + nnew), normal(nold + nnew), &
            dir(d, nold + nnew), friction(nold + nnew), gap(nold + nnew), load(nold + nnew), &
            impulse(d, nold + nnew), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the terrain contacts: "//trim(msg), &
                exit_other)
            return
        end if
        node(1:nold) = grid%contact_node
        axis(1:nold) = grid%contact_axis
        normal(1:nold) = grid%contact_normal
        dir(:, 1:nold) = grid%contact_dir
        friction(1:nold) = grid%contact_mu
        c = nold
        do id = 1, grid%nnodes
            x = terrain_node_position(id)
            call terrain_distance(grid%terrain, x, found, dist, n)
            if (.not. found) cycle
            c = c + 1
            node(c) = id
            axis(c) = 0
            normal(c) = 0.0_wp
            dir(:, c) = -n(1:d)
            friction(c) = mu
            grid%terrain_pair(id) = c
        end do
        gap = huge(1.0_wp)
        load = 0.0_wp
        call move_alloc(node, grid%contact_node)
        call move_alloc(axis, grid%contact_axis)
        call move_alloc(normal, grid%contact_normal)
        call move_alloc(dir, grid%contact_dir)
        call move_alloc(friction, grid%contact_mu)
        call move_alloc(gap, grid%contact_gap)
        call move_alloc(load, grid%contact_load)
        impulse = 0.0_wp
        grid%contact_impulse = impulse
        grid%contact_start = impulse
        call move_alloc(impulse, grid%contact_friction)
        grid%ncontacts = nold + nnew

    contains

        !> Position of node id from the whole grid's origin (z = 0 in 2D).
        function terrain_node_position(id) result(x)
            integer, intent(in) :: id
            real(wp) :: x(3)

            integer :: a, ijk(3)

            do a = 1, 3
                ijk(a) = node_layer(grid, id, a)
            end do
            x = base + grid%dx*real(ijk + shift, wp)
            if (d == 2) x(3) = 0.0_wp
        end function terrain_node_position

    end subroutine add_terrain

    !> Linear index of node (i, j, k), 0-based per direction.
    pure integer function node_index(grid, ijk)
        type(grid_type), intent(in) :: grid
            !! grid
        integer, intent(in) :: ijk(3)
            !! 0-based node coordinates
        node_index = 1 + ijk(1) + grid%nn(1)*(ijk(2) + grid%nn(2)*ijk(3))
    end function node_index

    !> Index of the (node, face) pair of node `id` on the face (side, axis) in the contact
    !> arrays, or 0 when the node is not on that face or the face is not frictional.
    !>
    !> Pairs of one face are numbered like its nodes, the lowest remaining axis fastest.
    pure integer function contact_index(grid, id, side, axis)
        type(grid_type), intent(in) :: grid
            !! grid
        integer, intent(in) :: id
            !! linear node index
        integer, intent(in) :: side
            !! 1: min face, 2: max face
        integer, intent(in) :: axis
            !! axis normal to the face

        integer :: r, ijk(3), b, stride

        contact_index = 0
        if (grid%contact_offset(side, axis) < 0) return
        r = id - 1
        ijk(1) = mod(r, grid%nn(1))
        r = r/grid%nn(1)
        ijk(2) = mod(r, grid%nn(2))
        ijk(3) = r/grid%nn(2)
        if (ijk(axis) /= merge(0, grid%nn(axis) - 1, side == 1)) return
        contact_index = grid%contact_offset(side, axis) + 1
        stride = 1
        do b = 1, 3
            if (b == axis) cycle
            contact_index = contact_index + ijk(b)*stride
            stride = stride*grid%nn(b)
        end do
    end function contact_index

    !> Position of node `id` [m].
    pure function node_position(grid, id) result(x)
        type(grid_type), intent(in) :: grid
            !! grid
        integer, intent(in) :: id
            !! linear node index
        real(wp) :: x(3)
            !! node position, z = origin(3) in 2D [m]

        integer :: r, ijk(3)

        r = id - 1
        ijk(1) = mod(r, grid%nn(1))
        r = r/grid%nn(1)
        ijk(2) = mod(r, grid%nn(2))
        ijk(3) = r/grid%nn(2)
        x = grid%origin + grid%dx*real(ijk, wp)
    end function node_position

    !> Bytes of nodal storage per node (mass, momentum, forces, velocity, acceleration,
    !> constraints; the frictional-face arrays and the scatter buffers of a pass not counted).
    pure integer function grid_bytes(grid)
        type(grid_type), intent(in) :: grid
            !! the grid
        grid_bytes = (storage_size(1.0_wp)/8)*(1 + 5*grid%dim) &
            + (storage_size(.true.)/8)*grid%dim
        ! XPIC: its field and the three of xpic_field (start, momentum kept, power)
        if (allocated(grid%xpic)) grid_bytes = grid_bytes + (storage_size(1.0_wp)/8)*4*grid%dim
    end function grid_bytes

    !> a = 0, writing only the blocks of a memory page that hold something else: the pages
    !> of zeros a fresh allocation maps are read, never written, and take no memory. The bits
    !> are compared, not the values: memory the heap hands out again may hold any pattern, a
    !> signalling NaN included (a floating-point comparison would trap in a Debug build).
    subroutine clear_reals(a)
        real(wp), contiguous, intent(inout), target :: a(:)
            !! array

        integer(int64), pointer, contiguous :: bits(:)
        integer :: i, last

        if (size(a) == 0) return
        ! one 64-bit integer per real(wp) (mpm_kinds: 15 digits)
        call c_f_pointer(c_loc(a), bits, [size(a)])
        do i = 1, size(a), page_entries
            last = min(size(a), i + page_entries - 1)
            if (any(bits(i:last) /= 0_int64)) a(i:last) = 0.0_wp
        end do
    end subroutine clear_reals

    !> a = 0 for a nodal vector field (clear_reals).
    subroutine clear_vectors(a)
        real(wp), contiguous, intent(inout), target :: a(:, :)
            !! array (components, nodes)

        real(wp), pointer, contiguous :: flat(:)

        flat(1:size(a)) => a
        call clear_reals(flat)
    end subroutine clear_vectors

    !> a = .false., writing only the blocks of a memory page that hold something else
    !> (clear_reals).
    subroutine clear_logicals(a)
        logical, contiguous, intent(inout), target :: a(:, :)
            !! array (components, nodes)

        logical, pointer, contiguous :: flat(:)
        integer :: i, last

        flat(1:size(a)) => a
        do i = 1, size(flat), page_entries
            last = min(size(flat), i + page_entries - 1)
            if (any(flat(i:last))) flat(i:last) = .false.
        end do
    end subroutine clear_logicals

end module mpm_grid
