!> Fill the bodies of a case with particles.
module mpm_bodies
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_case, only: case_type, initial_k0
    use mpm_case_sites, only: body_site_count, body_sites, particle_position
    use mpm_case_particle_list, only: particle_list_type
    use mpm_particles, only: particles_type, new_particles
    implicit none
    private
    public :: count_body_particles, create_particles, body_cell_histogram

    !> The sites (sub-cells) of a body and which of them hold a particle.
    type :: sites_type
        integer :: lo(3) = 0
            !! first sub-cell along each axis
        integer :: hi(3) = 0
            !! last sub-cell along each axis
        logical, allocatable :: inside(:, :, :)
            !! site holds a particle (polygon and STL bodies; a box holds all its sites)
        integer, allocatable :: above(:, :, :)
            !! with inside and the geostatic initial stress: the sites of the body that hold
            !! a particle above this one in its column (along the last axis)
    end type sites_type

contains

    !> Number of particles body b holds (mpm_case_sites::body_site_count); -1 when the memory
    !> to test the sites of an STL body cannot be allocated.
    integer(i8) function count_body_particles(case, b)
        type(case_type), intent(in) :: case
            !! resolved case (bodies 1..b set)
        integer, intent(in) :: b
            !! body index

        if (allocated(case%bodies(b)%list)) then
            count_body_particles = size(case%bodies(b)%list%volume, kind=i8)
        else
            count_body_particles = body_site_count(case%dim, case%domain, case%particles, &
                case%bodies, b)
        end if
    end function count_body_particles

    !> Create the particles of every body: positions, volumes, masses, velocities, sizes,
    !> and with initial_stress.type = "k0" their geostatic stresses (geostatic_stress).
    !>
    !> With `slab`, only the particles whose cell along axis slab(1) is in [slab(2), slab(3))
    !> (an image's part of the grid, mpm_decomposition), numbered in particles%id by their
    !> index among all particles.
    subroutine create_particles(case, particles, error, nstate, slab)
        type(case_type), intent(in) :: case
            !! resolved case
        type(particles_type), intent(out) :: particles
            !! the particles, body by body in case order
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated
        integer, intent(in), optional :: nstate
            !! material state variables per particle (default 0)
        integer, intent(in), optional :: slab(3)
            !! axis, first cell, one past the last cell of the particles to keep

        integer :: b, a, p, q, n, s(3), i, j, k, dim, pass, stat, first
        integer(i8) :: total
        integer :: lo(3), hi(3)
        real(wp) :: h, vol, x(3)
        character(len=256) :: msg
        type(sites_type), allocatable :: sites(:)

        dim = case%dim
        ! the sites of every body, tested once for the count and for both passes
        allocate (sites(size(case%bodies)))
        total = 0
        do b = 1, size(case%bodies)
            call body_sites(case%dim, case%domain, case%particles, case%bodies, b, sites(b)%lo, &
                sites(b)%hi, first, sites(b)%inside, error)
            if (allocated(error)) return
            if (allocated(case%bodies(b)%list)) then
                total = total + size(case%bodies(b)%list%volume, kind=i8)
            else if (allocated(sites(b)%inside)) then
                total = total + count(sites(b)%inside, kind=i8)
            else
                total = total + product(int(max(0, sites(b)%hi(1:dim) - sites(b)%lo(1:dim) &
                    + 1), i8))
            end if
        end do
        h = case%domain%dx/real(case%particles%ppc, wp)
        vol = h**dim
        if (case%initial_stress%type == initial_k0) then
            do b = 1, size(case%bodies)
                call count_above(sites(b), dim)
            end do
        end if
        if (.not. present(slab)) then
            call new_particles(particles, dim, int(total), error, nstate)
            if (allocated(error)) return
        end if
        ! with a slab: count the particles kept, then create them
        do pass = 1, merge(2, 1, present(slab))
            if (pass == 2) then
                call new_particles(particles, dim, q, error, nstate)
                if (allocated(error)) return
                allocate (particles%id(q), stat=stat, errmsg=msg)
                if (stat /= 0) then
                    call fatal_error(error, "cannot allocate the particle ids: "//trim(msg), &
                        exit_other)
                    return
                end if
            end if
            n = 0
            p = 0
            q = 0
            do b = 1, size(case%bodies)
                associate (body => case%bodies(b), &
                           rho => case%materials(case%bodies(b)%material)%density)
                    lo = sites(b)%lo
                    hi = sites(b)%hi
                    do k = lo(3), hi(3)
                        do j = lo(2), hi(2)
                            do i = lo(1), hi(1)
                                ! n numbers the sites (it seeds the jitter), p the particles
                                n = n + 1
                                if (allocated(sites(b)%inside)) then
                                    if (.not. sites(b)%inside(i, j, k)) cycle
                                end if
                                p = p + 1
                                s = [i, j, k]
                                x = particle_position(case%dim, case%domain, case%particles, s, n, h)
                                if (present(slab)) then
                                    a = global_cell_of(case, x(slab(1)), slab(1))
                                    if (a < slab(2) .or. a >= slab(3)) cycle
                                end if
                                q = q + 1
                                if (present(slab) .and. pass == 1) cycle
                                if (present(slab)) particles%id(q) = p
                                particles%x(:, q) = x(1:dim)
                                particles%v(:, q) = body%velocity(1:dim)
                                particles%volume(q) = vol
                                particles%volume0(q) = vol
                                particles%mass(q) = rho*vol
                                particles%lp0(:, q) = 0.5_wp*h
                                particles%material(q) = body%material
                                if (case%initial_stress%type == initial_k0) then
                                    call geostatic_stress(case, sites, s, h, body%material, &
                                        particles%stress(:, q))
                                end if
                                if (allocated(case%materials(body%material)%law)) then
                                    call case%materials(body%material)%law%initial_state( &
                                        x(1:dim), particles%state(:, q))
                                end if
                            end do
                        end do
                    end do
                end associate
                if (allocated(case%bodies(b)%list)) call add_listed(case%bodies(b)%list)
            end do
        end do

    contains

        !> The particles of a list (after the lattice ones of the same body).
        subroutine add_listed(list)
            type(particle_list_type), intent(in) :: list

            integer :: r, m

            do r = 1, size(list%volume)
                p = p + 1
                if (present(slab)) then
                    a = global_cell_of(case, list%x(slab(1), r), slab(1))
                    if (a < slab(2) .or. a >= slab(3)) cycle
                end if
                q = q + 1
                if (present(slab) .and. pass == 1) cycle
                if (present(slab)) particles%id(q) = p
                m = list%material(r)
                particles%x(:, q) = list%x(1:dim, r)
                particles%v(:, q) = case%bodies(b)%velocity(1:dim)
                particles%volume(q) = list%volume(r)
                particles%volume0(q) = list%volume(r)
                particles%mass(q) = case%materials(m)%density*list%volume(r)
                particles%lp0(:, q) = 0.5_wp*list%volume(r)**(1.0_wp/real(dim, wp))
                particles%material(q) = m
                if (allocated(list%stress)) particles%stress(:, q) = list%stress(:, r)
                if (allocated(case%materials(m)%law)) then
                    call case%materials(m)%law%initial_state(list%x(1:dim, r), &
                        particles%state(:, q))
                end if
            end do
        end subroutine add_listed

    end subroutine create_particles

    !> For each site of a polygon or surface body, the sites of the body above it in its
    !> column that hold a particle (sites%above; nothing for a box).
    subroutine count_above(sites, dim)
        type(sites_type), intent(inout) :: sites
            !! the body's sites
        integer, intent(in) :: dim
            !! number of space dimensions

        integer :: i, j, k, n

        if (.not. allocated(sites%inside)) return
        allocate (sites%above(sites%lo(1):sites%hi(1), sites%lo(2):sites%hi(2), &
            sites%lo(3):sites%hi(3)))
        if (dim == 2) then
            do i = sites%lo(1), sites%hi(1)
                n = 0
                do j = sites%hi(2), sites%lo(2), -1
                    sites%above(i, j, 0) = n
                    if (sites%inside(i, j, 0)) n = n + 1
                end do
            end do
        else
            do j = sites%lo(2), sites%hi(2)
                do i = sites%lo(1), sites%hi(1)
                    n = 0
                    do k = sites%hi(3), sites%lo(3), -1
                        sites%above(i, j, k) = n
                        if (sites%inside(i, j, k)) n = n + 1
                    end do
                end do
            end do
        end if
    end subroutine count_above

    !> The geostatic stress of the particle of site s (initial_stress.type = "k0"): the
    !> vertical stress (along the last axis, which gravity points down) is the weight per
    !> unit area of the material above the particle's centre, rho g h for every site above
    !> it in its column, whatever body holds it, and half its own; the horizontal stresses
    !> K0 times it, the shear stresses zero. Tension positive.
    pure subroutine geostatic_stress(case, sites, s, h, material, stress)
        type(case_type), intent(in) :: case
            !! resolved case
        type(sites_type), intent(in) :: sites(:)
            !! the sites of every body, with the counts above (count_above)
        integer, intent(in) :: s(3)
            !! the particle's site
        real(wp), intent(in) :: h
            !! site size [m]
        integer, intent(in) :: material
            !! the particle's material
        real(wp), intent(out) :: stress(:)
            !! its stress (Voigt) [Pa]

        integer :: b, dim
        real(wp) :: load, k0

        dim = case%dim
        load = 0.5_wp*case%materials(material)%density
        do b = 1, size(sites)
            load = load + case%materials(case%bodies(b)%material)%density &
                *real(sites_above(sites(b), dim, s), wp)
        end do
        load = load*abs(case%gravity(dim))*h
        k0 = case%initial_stress%k0_material(material)
        stress = 0.0_wp
        stress(1:3) = -k0*load
        stress(dim) = -load
    end subroutine geostatic_stress

    !> The sites of a body that hold a particle above site s, in its column (none when the
    !> column is not the body's).
    pure integer function sites_above(sites, dim, s)
        type(sites_type), intent(in) :: sites
            !! the body's sites
        integer, intent(in) :: dim
            !! number of space dimensions
        integer, intent(in) :: s(3)
            !! the site

        integer :: c(3), w

        sites_above = 0
        if (any(s(1:dim - 1) < sites%lo(1:dim - 1) .or. s(1:dim - 1) > sites%hi(1:dim - 1))) then
            return
        end if
        w = s(dim)
        if (w >= sites%hi(dim)) return
        if (.not. allocated(sites%inside)) then
            ! a box: every site of the column above
            sites_above = sites%hi(dim) - max(w, sites%lo(dim) - 1)
            return
        end if
        c = s
        if (w < sites%lo(dim)) then
            ! below the body's range: all of the column
            c(dim) = sites%lo(dim)
            sites_above = sites%above(c(1), c(2), c(3))
            if (sites%inside(c(1), c(2), c(3))) sites_above = sites_above + 1
        else
            sites_above = sites%above(c(1), c(2), c(3))
        end if
    end function sites_above

    !> Particles per cell layer along axis a, of all the particles the bodies hold.
    subroutine body_cell_histogram(case, a, histogram)
        type(case_type), intent(in) :: case
            !! resolved case
        integer, intent(in) :: a
            !! axis
        integer(i8), intent(out) :: histogram(0:)
            !! particles per cell layer (0 : ncells(a) - 1)

        integer :: b, n, s(3), i, j, k, lo(3), hi(3), c, first
        real(wp) :: h, x(3)
        logical, allocatable :: inside(:, :, :)
        type(error_type), allocatable :: error

        histogram = 0
        h = case%domain%dx/real(case%particles%ppc, wp)
        n = 0
        do b = 1, size(case%bodies)
            ! out of memory: every site of the bounding box counts (only the balance suffers;
            ! create_particles then reports the error)
            call body_sites(case%dim, case%domain, case%particles, case%bodies, b, lo, hi, first, &
                inside, error)
            do k = lo(3), hi(3)
                do j = lo(2), hi(2)
                    do i = lo(1), hi(1)
                        n = n + 1
                        if (allocated(inside)) then
                            if (.not. inside(i, j, k)) cycle
                        end if
                        s = [i, j, k]
                        x = particle_position(case%dim, case%domain, case%particles, s, n, h)
                        c = global_cell_of(case, x(a), a)
                        histogram(c) = histogram(c) + 1
                    end do
                end do
            end do
            if (allocated(case%bodies(b)%list)) then
                do i = 1, size(case%bodies(b)%list%volume)
                    c = global_cell_of(case, case%bodies(b)%list%x(a, i), a)
                    histogram(c) = histogram(c) + 1
                end do
            end if
        end do
    end subroutine body_cell_histogram

    !> Cell (0-based, along axis a) of a coordinate in the whole grid, clamped to the grid
    !> (as mpm_decomposition's global_cell).
    pure integer function global_cell_of(case, x, a)
        type(case_type), intent(in) :: case
        real(wp), intent(in) :: x
        integer, intent(in) :: a
        global_cell_of = min(max(int((x - case%domain%origin(a))/case%domain%dx), 0), &
            case%domain%ncells(a) - 1)
    end function global_cell_of

end module mpm_bodies
