!> The images' parts of the grid (slabs along one axis) through a run: the first cut by the
!> particles of the bodies or of a state file, the grid and terrain pairs of a slab, the
!> particles that cross a cut, and new cuts when the particle counts drift apart.
!> Collective where noted; on one image the slab is the whole grid.
module mpm_solver_slabs
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_input, exit_other
    use mpm_grid, only: new_grid, add_terrain
    use mpm_terrain, only: terrain_misses_domain
    use mpm_particles, only: pack_particles, rebuild_particles
    use mpm_bodies, only: body_cell_histogram
    use mpm_decomposition, only: decomposition_type, new_decomposition, cut_axis, local_case, &
        global_cell
    use mpm_parallel, only: image_count, image_id, sum_over_images, max_over_images, &
        exchange_neighbours
    use mpm_contact_loads, only: face_loads, take_face_loads, terrain_loads, take_terrain_loads
    use mpm_stencil, only: stencils_type
    use mpm_simulation, only: simulation_type, start_type, agree
    implicit none
    private
    public :: slab_grid, terrain_contact, rebalance, decompose_bodies, decompose_loaded, &
        migrate_particles

    integer, parameter :: rebalance_steps = 50
        !! steps between two looks at the particle counts of the images
    real(wp), parameter :: rebalance_threshold = 1.1_wp
        !! the cuts move when the busiest image holds more than this times the mean count

contains

    !> The grid of this image's part of the decomposition (the whole grid on one image).
    subroutine slab_grid(sim, error)
        type(simulation_type), intent(inout) :: sim
            !! the simulation (case and decomposition set)
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        call new_grid(sim%grid, local_case(sim%case, sim%dec), error)
        if (allocated(error)) return
        if (sim%dec%axis > 0) then
            sim%grid%halo_axis = sim%dec%axis
            sim%grid%halo_left = sim%dec%left
            sim%grid%halo_right = sim%dec%right
            sim%grid%owned_lo = sim%dec%cell_lo - sim%dec%node_lo
            sim%grid%owned_hi = sim%dec%cell_hi - sim%dec%node_lo - 1
            if (sim%dec%right == 0) sim%grid%owned_hi = sim%grid%owned_hi + 1
        end if
        ! frictional faces average the normal impulse over five wave transits of a cell (the
        ! weight 0.1 per step it had at CFL 0.5), so that a smaller step does not shorten it
        sim%grid%contact_time = 5.0_wp*sim%case%domain%dx/max(maxval(sim%wave_speed), tiny(1.0_wp))
    end subroutine slab_grid

    !> Frictional contact with the terrain surface of contact.file (read by the set-up
    !> layer, kept for the grids of later cuts). Collective.
    subroutine terrain_contact(sim, error, start)
        type(simulation_type), intent(inout) :: sim
            !! the simulation, with its grid
        type(error_type), allocatable, intent(out) :: error
            !! set when the surface was not read or misses the domain
        type(start_type), intent(inout), optional :: start
            !! its terrain corners move into the simulation

        logical :: read

        read = .false.
        if (present(start)) read = allocated(start%terrain_corner)
        if (.not. read) then
            call fatal_error(error, sim%case%file//": new_simulation: the terrain surface "// &
                "of contact.file was not read (mpm_setup::read_start reads it)", exit_other)
            return
        end if
        call move_alloc(start%terrain_corner, sim%terrain_corner)
        call slab_terrain(sim, error)
    end subroutine terrain_contact

    !> The terrain pairs of this image's grid: nodes placed as in the whole grid, so that
    !> the images sharing a node give it the same pair; the surface must come within reach
    !> of some image's slab. Collective.
    subroutine slab_terrain(sim, error)
        type(simulation_type), intent(inout) :: sim
            !! the simulation, its grid just made by slab_grid
        type(error_type), allocatable, intent(out) :: error
            !! set when the surface misses the domain or memory cannot be allocated

        integer :: offset(3), near

        offset = 0
        if (sim%dec%axis > 0) offset(sim%dec%axis) = sim%dec%node_lo
        call add_terrain(sim%grid, sim%terrain_corner, sim%case%contact%mu, sim%case%gravity, &
            error, global_origin=sim%case%domain%origin, offset=offset, &
            allow_empty=image_count() > 1)
        if (image_count() > 1) then
            call agree(error)
            if (.not. allocated(error)) then
                ! the surface misses the domain when it misses every slab (one message)
                near = 0
                if (size(sim%grid%terrain%list) > 0) near = 1
                call max_over_images(near)
                if (near == 0) then
                    call fatal_error(error, terrain_misses_domain, exit_input)
                    if (image_id() /= 1) error%message = ""
                end if
            end if
        end if
        if (allocated(error)) then
            if (len(error%message) > 0) error%message = sim%case%file//': contact.file = "'// &
                sim%case%contact%file//'": '//error%message
        end if
    end subroutine slab_terrain

    !> Move the cuts when the particle counts of the images drift apart (a flow that travels
    !> into other slabs): every `rebalance_steps` steps the particles per cell layer are
    !> summed over the images, and when the busiest image holds more than
    !> `rebalance_threshold` times the mean, the cuts are set again as at the start. The
    !> particles then go to their new images (neighbour by neighbour), each image builds the
    !> grid of its new slab (and its terrain pairs), and the running contact loads of the
    !> frictional faces and the terrain (the only nodal state kept from step to step) follow
    !> their nodes. Collective.
    subroutine rebalance(sim, error)
        type(simulation_type), intent(inout) :: sim
            !! the simulation after a step
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        integer(i8), allocatable :: histogram(:)
        type(decomposition_type) :: dec
        real(wp), allocatable :: loads(:), terrain_load(:)
        integer(i8), allocatable :: terrain_node(:)
        real(wp) :: small_mass, light_mass, imbalance
        integer :: axis, p, c, k, misplaced
        logical :: complete

        if (sim%dec%axis == 0 .or. mod(sim%step, int(rebalance_steps, i8)) /= 0) return
        axis = sim%dec%axis
        allocate (histogram(0:sim%case%domain%ncells(axis) - 1))
        histogram = 0
        do p = 1, sim%particles%n
            c = global_cell(sim%case, sim%particles%x(axis, p), axis)
            histogram(c) = histogram(c) + 1
        end do
        call sum_over_images(histogram)
        imbalance = 0.0_wp
        do k = 1, sim%dec%images
            imbalance = max(imbalance, real(sum(histogram(sim%dec%cuts(k - 1): &
                sim%dec%cuts(k) - 1)), wp))
        end do
        imbalance = imbalance*real(sim%dec%images, wp)/max(1.0_wp, real(sum(histogram), wp))
        if (imbalance <= rebalance_threshold) return
        call new_decomposition(dec, sim%case, sim%dec%images, sim%dec%me, histogram, error)
        if (allocated(error)) return
        if (all(dec%cuts == sim%dec%cuts)) return
        call face_loads(sim%case, sim%grid, sim%dec, loads)
        call terrain_loads(sim%case, sim%grid, sim%dec, terrain_node, terrain_load)
        sim%dec = dec
        ! the particles to their new slabs: one neighbour per pass
        do
            misplaced = 0
            do p = 1, sim%particles%n
                c = global_cell(sim%case, sim%particles%x(axis, p), axis)
                if (c < dec%cell_lo .or. c >= dec%cell_hi) misplaced = misplaced + 1
            end do
            call max_over_images(misplaced)
            if (misplaced == 0) exit
            call migrate_particles(sim, error)
            call agree(error)
            if (allocated(error)) return
        end do
        small_mass = sim%grid%small_mass
        light_mass = sim%grid%light_mass
        call slab_grid(sim, error)
        call agree(error)
        if (allocated(error)) return
        if (allocated(sim%terrain_corner)) then
            call slab_terrain(sim, error)
            if (allocated(error)) return
        end if
        sim%grid%small_mass = small_mass
        sim%grid%light_mass = light_mass
        call take_face_loads(sim%case, sim%grid, sim%dec, loads)
        call take_terrain_loads(sim%case, sim%grid, sim%dec, terrain_node, terrain_load, &
            complete)
        if (.not. complete) then
            call fatal_error(error, "internal error: a terrain contact pair of the new cuts "// &
                "had no load before them")
        end if
        call agree(error)
        if (allocated(error)) return
        ! the stencil tables follow the new grid
        sim%stencils = stencils_type()
    end subroutine rebalance

    !> Cut the grid among the images by the particles the bodies will hold.
    subroutine decompose_bodies(sim, error)
        type(simulation_type), intent(inout) :: sim
            !! the simulation (case set)
        type(error_type), allocatable, intent(out) :: error
            !! set when the grid cannot be cut for the images

        integer(i8), allocatable :: histogram(:)
        integer :: axis

        axis = cut_axis(sim%case)
        allocate (histogram(0:sim%case%domain%ncells(axis) - 1))
        call body_cell_histogram(sim%case, axis, histogram)
        call new_decomposition(sim%dec, sim%case, image_count(), image_id(), histogram, error)
    end subroutine decompose_bodies

    !> Cut the grid among the images by the loaded particles (every image read them all), and
    !> keep this image's; ids are the indices in the state file.
    subroutine decompose_loaded(sim, error)
        type(simulation_type), intent(inout) :: sim
            !! the simulation, with every particle of the state file
        type(error_type), allocatable, intent(out) :: error
            !! set when the grid cannot be cut for the images

        integer(i8), allocatable :: histogram(:)
        integer :: axis, p, c
        logical, allocatable :: keep(:)

        if (image_count() == 1) then
            call new_decomposition(sim%dec, sim%case, 1, 1, [integer(i8) ::], error)
            return
        end if
        associate (particles => sim%particles)
            axis = cut_axis(sim%case)
            allocate (histogram(0:sim%case%domain%ncells(axis) - 1), keep(particles%n))
            histogram = 0
            do p = 1, particles%n
                c = global_cell(sim%case, particles%x(axis, p), axis)
                histogram(c) = histogram(c) + 1
            end do
            call new_decomposition(sim%dec, sim%case, image_count(), image_id(), histogram, &
                error)
            if (allocated(error)) return
            do p = 1, particles%n
                c = global_cell(sim%case, particles%x(axis, p), axis)
                keep(p) = c >= sim%dec%cell_lo .and. c < sim%dec%cell_hi
            end do
            particles%id = [(p, p = 1, particles%n)]
            call rebuild_particles(particles, keep, [real(wp) ::], error)
        end associate
    end subroutine decompose_loaded

    !> Send the particles that left this image's slab to the neighbour that owns them now
    !> (a particle moves less than a cell per step: to a neighbour at most), and take in
    !> those that arrived. Collective.
    subroutine migrate_particles(sim, error)
        type(simulation_type), intent(inout) :: sim
            !! the simulation after a step
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        integer :: p, c, axis
        logical, allocatable :: to_left(:), to_right(:)
        real(wp), allocatable :: send_left(:), send_right(:), recv_left(:), recv_right(:)

        if (sim%dec%axis == 0) return
        axis = sim%dec%axis
        associate (particles => sim%particles)
            allocate (to_left(particles%n), to_right(particles%n))
            do p = 1, particles%n
                c = global_cell(sim%case, particles%x(axis, p), axis)
                to_left(p) = c < sim%dec%cell_lo
                to_right(p) = c >= sim%dec%cell_hi
            end do
            call pack_particles(particles, to_left, send_left)
            call pack_particles(particles, to_right, send_right)
            call exchange_neighbours(sim%dec%left, sim%dec%right, send_left, send_right, &
                recv_left, recv_right)
            ! most steps move no particle across a cut: the arrays stay as they are
            if (size(send_left) + size(send_right) + size(recv_left) + size(recv_right) > 0) then
                call rebuild_particles(particles, .not. (to_left .or. to_right), &
                    [recv_left, recv_right], error)
            end if
        end associate
    end subroutine migrate_particles
end module mpm_solver_slabs
