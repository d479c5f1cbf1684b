!> Where the particles of the bodies sit: the sub-cells (sites) of each body and, for a body
!> bounded by a closed STL surface, which sites lie inside it.
!>
!> Geometry of the case only (domain, particles, bodies): the case reader counts the particles
!> of each body with it, and `mpm_bodies` fills the bodies from the same sites, so the count
!> and the particles always agree.
module mpm_case_sites
    use mpm_kinds, only: wp, i8
    use mpm_error, only: error_type, fatal_error, exit_other
    use mpm_case_domain, only: domain_section_type
    use mpm_case_particles, only: particles_section_type, dist_random
    use mpm_case_bodies, only: body_spec_type, is_box, inside_shape, shape_none
    implicit none
    private
    public :: body_site_count, body_shared_sites, body_sites, body_subcell_range, &
        particle_position

    ! Shift of the test line off the particle, in sub-cells along the two axes across it:
    ! irrational fractions, so the line never meets an edge or a corner of a mesh whose
    ! coordinates are round numbers.
    real(wp), parameter :: shift_u = 1.0e-7_wp*sqrt(2.0_wp)
    real(wp), parameter :: shift_v = 1.0e-7_wp*sqrt(3.0_wp)

contains

    !> Number of particles body b holds: every site of its sub-cell range for a box, the sites
    !> inside the closed surface for an STL body (see body_sites); -1 when the memory to test
    !> the sites of an STL body cannot be allocated.
    integer(i8) function body_site_count(dim, domain, particles, bodies, b)
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell and their placement
        type(body_spec_type), intent(in) :: bodies(:)
            !! bodies 1..b set
        integer, intent(in) :: b
            !! body index

        integer :: lo(3), hi(3), a, first
        logical, allocatable :: inside(:, :, :)
        type(error_type), allocatable :: error

        call body_sites(dim, domain, particles, bodies, b, lo, hi, first, inside, error)
        if (allocated(error)) then
            body_site_count = -1_i8
        else if (allocated(inside)) then
            body_site_count = count(inside, kind=i8)
        else
            body_site_count = 1_i8
            do a = 1, dim
                body_site_count = body_site_count*int(max(0, hi(a) - lo(a) + 1), i8)
            end do
        end if
    end function body_site_count

    !> Number of particle sites (sub-cells) that bodies i and j both hold: a box holds every
    !> site of its range, a polygon or a surface the sites whose particle lies inside (see
    !> body_sites); -1 when the memory to test the sites cannot be allocated.
    integer(i8) function body_shared_sites(dim, domain, particles, bodies, i, j)
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell and their placement
        type(body_spec_type), intent(in) :: bodies(:)
            !! bodies 1..max(i, j) set
        integer, intent(in) :: i, j
            !! the two bodies

        integer :: lo(3, 2), hi(3, 2), l(3), u(3), first, x, y, z
        logical, allocatable :: in_i(:, :, :), in_j(:, :, :)
        type(error_type), allocatable :: error

        body_shared_sites = -1_i8
        call body_sites(dim, domain, particles, bodies, i, lo(:, 1), hi(:, 1), first, in_i, &
            error)
        if (allocated(error)) return
        call body_sites(dim, domain, particles, bodies, j, lo(:, 2), hi(:, 2), first, in_j, &
            error)
        if (allocated(error)) return
        l = max(lo(:, 1), lo(:, 2))
        u = min(hi(:, 1), hi(:, 2))
        body_shared_sites = 0_i8
        do z = l(3), u(3)
            do y = l(2), u(2)
                do x = l(1), u(1)
                    if (holds(in_i, x, y, z) .and. holds(in_j, x, y, z)) then
                        body_shared_sites = body_shared_sites + 1_i8
                    end if
                end do
            end do
        end do

    contains

        !> Whether a body holds site (x, y, z): every site of a box's range.
        pure logical function holds(inside, x, y, z)
            logical, allocatable, intent(in) :: inside(:, :, :)
                !! the sites of a polygon or surface inside it, with their ranges' bounds
            integer, intent(in) :: x, y, z
                !! the site

            holds = .true.
            if (allocated(inside)) holds = inside(x, y, z)
        end function holds

    end function body_shared_sites

    !> Range of particle sub-cells of a body along each axis (0-based, inclusive).
    !>
    !> Particles sit at the centres of a regular sub-grid of spacing h = dx / ppc:
    !> x_s = origin + (s + 1/2) h, s = 0 .. ncells * ppc - 1. A body holds the particles whose
    !> sub-cell centre lies in [min, max) along every axis. A body holds no particle when
    !> hi(a) < lo(a) for some axis.
    pure subroutine body_subcell_range(dim, domain, particles, body, lo, hi)
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell
        type(body_spec_type), intent(in) :: body
            !! the body
        integer, intent(out) :: lo(3)
            !! first sub-cell along each axis (0 for unused axes)
        integer, intent(out) :: hi(3)
            !! last sub-cell along each axis (0 for unused axes)

        integer :: a, nsub
        real(wp) :: h

        lo = 0
        hi = 0
        h = domain%dx/real(particles%ppc, wp)
        do a = 1, dim
            nsub = domain%ncells(a)*particles%ppc
            lo(a) = max(0, ceiling((body%xmin(a) - domain%origin(a))/h - 0.5_wp))
            hi(a) = min(nsub - 1, ceiling((body%xmax(a) - domain%origin(a))/h - 0.5_wp) - 1)
        end do
        ! a particle list has no sites
        if (allocated(body%list)) hi = lo - 1
    end subroutine body_subcell_range

    !> Sites (sub-cells, see body_subcell_range) of body b and, for an STL body, which of
    !> them hold a particle.
    !>
    !> A site of an STL body holds a particle when its particle position lies inside the closed
    !> surface: an odd number of the surface's crossings with a line through the position lie
    !> below it. The line is parallel to z through (x, y) in 3D; in 2D the body is the section
    !> of the surface by z = 0 and the line is parallel to y through (x, 0). The crossings are
    !> gathered column by column (a column is the sub-cells with the same x, and the same y in
    !> 3D): each triangle visits only the columns its projected bounding box covers.
    subroutine body_sites(dim, domain, particles, bodies, b, lo, hi, first, inside, error)
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell and their placement
        type(body_spec_type), intent(in) :: bodies(:)
            !! bodies 1..b set
        integer, intent(in) :: b
            !! body index
        integer, intent(out) :: lo(3)
            !! first sub-cell of the body along each axis
        integer, intent(out) :: hi(3)
            !! last sub-cell of the body along each axis
        integer, intent(out) :: first
            !! sites of the bodies before b (numbers the jitter of the random distribution)
        logical, allocatable, intent(out) :: inside(:, :, :)
            !! (lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)) site holds a particle; not allocated
            !! for a box, whose sites all hold one
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        integer :: c, l(3), u(3), stat
        character(len=256) :: msg

        first = 0
        do c = 1, b - 1
            call body_subcell_range(dim, domain, particles, bodies(c), l, u)
            first = first + product(max(0, u(1:dim) - l(1:dim) + 1))
        end do
        call body_subcell_range(dim, domain, particles, bodies(b), lo, hi)
        if (is_box(bodies(b))) return
        allocate (inside(lo(1):hi(1), lo(2):hi(2), lo(3):hi(3)), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the sites of body '" &
                //bodies(b)%name//"': "//trim(msg), exit_other)
            return
        end if
        inside = .false.
        if (any(hi(1:dim) < lo(1:dim))) return
        if (bodies(b)%shape /= shape_none) then
            call fill_shape(dim, domain, particles, bodies(b), lo, hi, first, inside)
        else if (allocated(bodies(b)%bottom)) then
            call fill_layer(dim, domain, particles, bodies(b), lo, hi, first, inside, error)
        else
            call fill_surface(dim, domain, particles, bodies(b)%triangle, lo, hi, first, &
                inside, error)
        end if
    end subroutine body_sites

    !> Mark the sites of a layer: their particle lies below the top surface (which its line
    !> crosses, no crossing below it) and above the bottom one (a crossing below it).
    subroutine fill_layer(dim, domain, particles, body, lo, hi, first, inside, error)
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell and their placement
        type(body_spec_type), intent(in) :: body
            !! the layer
        integer, intent(in) :: lo(3)
            !! first sub-cell along each axis
        integer, intent(in) :: hi(3)
            !! last sub-cell along each axis
        integer, intent(in) :: first
            !! sites of the bodies before this one
        logical, intent(inout) :: inside(lo(1):, lo(2):, lo(3):)
            !! site holds a particle
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated

        integer, allocatable :: below_top(:, :, :), all_top(:, :, :), below_bottom(:, :, :)
        integer :: stat
        character(len=256) :: msg

        allocate (below_top, all_top, below_bottom, mold=merge(0, 0, inside), stat=stat, &
            errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the sites of body '"//body%name//"': " &
                //trim(msg), exit_other)
            return
        end if
        call fill_surface(dim, domain, particles, body%triangle, lo, hi, first, inside, error, &
            below_top, all_top)
        if (allocated(error)) return
        call fill_surface(dim, domain, particles, body%bottom, lo, hi, first, inside, error, &
            below_bottom)
        if (allocated(error)) return
        inside = all_top > 0 .and. below_top == 0 .and. below_bottom > 0
    end subroutine fill_layer

    !> Mark the sites whose particle lies inside a body's analytic shape (see body_sites).
    pure subroutine fill_shape(dim, domain, particles, body, lo, hi, first, inside)
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell and their placement
        type(body_spec_type), intent(in) :: body
            !! the body
        integer, intent(in) :: lo(3)
            !! first sub-cell along each axis
        integer, intent(in) :: hi(3)
            !! last sub-cell along each axis
        integer, intent(in) :: first
            !! sites of the bodies before this one
        logical, intent(inout) :: inside(lo(1):, lo(2):, lo(3):)
            !! site holds a particle

        integer :: i, j, k, n
        real(wp) :: h

        h = domain%dx/real(particles%ppc, wp)
        n = first
        do k = lo(3), hi(3)
            do j = lo(2), hi(2)
                do i = lo(1), hi(1)
                    n = n + 1
                    inside(i, j, k) = inside_shape(body, particle_position(dim, domain, &
                        particles, [i, j, k], n, h))
                end do
            end do
        end do
    end subroutine fill_shape

    !> Mark the sites whose particle lies inside a closed surface (see body_sites).
    subroutine fill_surface(dim, domain, particles, triangle, lo, hi, first, inside, error, &
            below_count, column_count)
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell and their placement
        real(wp), intent(in) :: triangle(:, :, :)
            !! corners (coordinate, corner, triangle) of the closed surface [m]
        integer, intent(in) :: lo(3)
            !! first sub-cell along each axis
        integer, intent(in) :: hi(3)
            !! last sub-cell along each axis
        integer, intent(in) :: first
            !! sites of the bodies before this one
        logical, intent(inout) :: inside(lo(1):, lo(2):, lo(3):)
            !! site holds a particle (false on entry)
        type(error_type), allocatable, intent(out) :: error
            !! set when memory cannot be allocated
        integer, intent(out), optional :: below_count(lo(1):, lo(2):, lo(3):)
            !! per site, the crossings of its line below its particle
        integer, intent(out), optional :: column_count(lo(1):, lo(2):, lo(3):)
            !! per site, all the crossings of its line

        integer :: va, wa, nu, nv, ncol, t, iu, iv, c, m, s(3), n, k, stat, below
        integer :: range(2, 2)
        integer, allocatable :: start(:), fill(:), member(:)
        real(wp), allocatable :: crossing(:)
        real(wp) :: h, x(3), point(2), last(2)
        character(len=256) :: msg

        ! u = x; v and w: the axes across and along the line
        va = merge(2, 3, dim == 3)
        wa = merge(3, 2, dim == 3)
        h = domain%dx/real(particles%ppc, wp)
        nu = hi(1) - lo(1) + 1
        nv = 1
        if (dim == 3) nv = hi(2) - lo(2) + 1
        ncol = nu*nv
        allocate (start(ncol + 1), fill(ncol), stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the columns of a body: "//trim(msg), &
                exit_other)
            return
        end if
        ! columns covered by each triangle: count, then list (compressed rows)
        start = 0
        do t = 1, size(triangle, 3)
            if (.not. covered(t, range)) cycle
            do iv = range(1, 2), range(2, 2)
                do iu = range(1, 1), range(2, 1)
                    c = column(iu, iv)
                    start(c + 1) = start(c + 1) + 1
                end do
            end do
        end do
        start(1) = 1
        do c = 1, ncol
            start(c + 1) = start(c + 1) + start(c)
        end do
        allocate (member(start(ncol + 1) - 1), crossing(maxval(start(2:) - start(:ncol)) + 1), &
            stat=stat, errmsg=msg)
        if (stat /= 0) then
            call fatal_error(error, "cannot allocate the crossings of a body: "//trim(msg), &
                exit_other)
            return
        end if
        fill = start(1:ncol)
        do t = 1, size(triangle, 3)
            if (.not. covered(t, range)) cycle
            do iv = range(1, 2), range(2, 2)
                do iu = range(1, 1), range(2, 1)
                    c = column(iu, iv)
                    member(fill(c)) = t
                    fill(c) = fill(c) + 1
                end do
            end do
        end do
        ! the sites of each column, bottom up; crossings recomputed when the line moves
        ! (with the random distribution every particle has its own line)
        do iv = merge(lo(2), 0, dim == 3), merge(hi(2), 0, dim == 3)
            do iu = lo(1), hi(1)
                c = column(iu, iv)
                last = huge(1.0_wp)
                m = 0
                do k = lo(wa), hi(wa)
                    s = 0
                    s(1) = iu
                    s(wa) = k
                    if (dim == 3) s(2) = iv
                    n = first + 1 + (s(1) - lo(1)) + nu*((s(2) - lo(2)) &
                        + (hi(2) - lo(2) + 1)*(s(3) - lo(3)))
                    x = particle_position(dim, domain, particles, s, n, h)
                    point = [x(1) + shift_u*h, shift_v*h]
                    if (dim == 3) point(2) = point(2) + x(2)
                    if (any(point /= last)) then
                        call column_crossings(point, c, m)
                        last = point
                    end if
                    below = count(crossing(1:m) < x(wa))
                    inside(s(1), s(2), s(3)) = modulo(below, 2) == 1
                    if (present(below_count)) below_count(s(1), s(2), s(3)) = below
                    if (present(column_count)) column_count(s(1), s(2), s(3)) = m
                end do
            end do
        end do

    contains

        !> Column number (1-based) of sub-cell column (iu, iv).
        pure integer function column(iu, iv)
            integer, intent(in) :: iu
                !! sub-cell along x
            integer, intent(in) :: iv
                !! sub-cell along y (3D), 0 (2D)
            column = iu - lo(1) + 1
            if (dim == 3) column = column + nu*(iv - lo(2))
        end function column

        !> Whether triangle t's projection can meet a column line, and the columns it covers.
        logical function covered(t, range)
            integer, intent(in) :: t
                !! triangle
            integer, intent(out) :: range(2, 2)
                !! first and last column along u (:, 1) and v (:, 2)

            real(wp) :: box(2, 2)

            box(1, 1) = minval(triangle(1, :, t))
            box(2, 1) = maxval(triangle(1, :, t))
            box(1, 2) = minval(triangle(va, :, t))
            box(2, 2) = maxval(triangle(va, :, t))
            range(1, 1) = max(lo(1), floor((box(1, 1) - domain%origin(1))/h))
            range(2, 1) = min(hi(1), floor((box(2, 1) - domain%origin(1))/h))
            if (dim == 3) then
                range(1, 2) = max(lo(2), floor((box(1, 2) - domain%origin(2))/h))
                range(2, 2) = min(hi(2), floor((box(2, 2) - domain%origin(2))/h))
            else
                ! the line of a 2D case runs in the plane z = 0 (shifted)
                range(:, 2) = 0
                if (box(1, 2) > shift_v*h .or. box(2, 2) < shift_v*h) range(2, 2) = -1
            end if
            covered = all(range(1, :) <= range(2, :))
        end function covered

        !> Sorted heights (along w) of the crossings of the line through point with the
        !> triangles listed for column c.
        subroutine column_crossings(point, c, m)
            real(wp), intent(in) :: point(2)
                !! where the line crosses the (u, v) plane [m]
            integer, intent(in) :: c
                !! column
            integer, intent(out) :: m
                !! crossings found, in crossing(1:m)

            integer :: e, t, r
            real(wp) :: a(2), bb(2), cc(2), d(3), z

            m = 0
            do e = start(c), start(c + 1) - 1
                t = member(e)
                a = [triangle(1, 1, t), triangle(va, 1, t)]
                bb = [triangle(1, 2, t), triangle(va, 2, t)]
                cc = [triangle(1, 3, t), triangle(va, 3, t)]
                ! twice the signed areas of the sub-triangles opposite c, a and b
                d(1) = (bb(1) - a(1))*(point(2) - a(2)) - (bb(2) - a(2))*(point(1) - a(1))
                d(2) = (cc(1) - bb(1))*(point(2) - bb(2)) - (cc(2) - bb(2))*(point(1) - bb(1))
                d(3) = (a(1) - cc(1))*(point(2) - cc(2)) - (a(2) - cc(2))*(point(1) - cc(1))
                if (.not. (all(d > 0.0_wp) .or. all(d < 0.0_wp))) cycle
                z = (d(2)*triangle(wa, 1, t) + d(3)*triangle(wa, 2, t) &
                    + d(1)*triangle(wa, 3, t))/sum(d)
                ! insertion: the list stays sorted
                r = m
                do while (r > 0)
                    if (crossing(r) <= z) exit
                    crossing(r + 1) = crossing(r)
                    r = r - 1
                end do
                crossing(r + 1) = z
                m = m + 1
            end do
        end subroutine column_crossings

    end subroutine fill_surface

    !> Position of the particle of site p (index among the sites of all bodies, which seeds its
    !> jitter) in sub-cell s of spacing h.
    pure function particle_position(dim, domain, particles, s, p, h) result(x)
        integer, intent(in) :: dim
            !! number of space dimensions
        type(domain_section_type), intent(in) :: domain
            !! the grid
        type(particles_section_type), intent(in) :: particles
            !! particles per cell and their placement
        integer, intent(in) :: s(3)
            !! sub-cell along each axis (0 for unused axes)
        integer, intent(in) :: p
            !! site index
        real(wp), intent(in) :: h
            !! sub-cell size [m]
        real(wp) :: x(3)
            !! position (0 for unused axes) [m]

        integer :: a
        real(wp) :: jitter(3)

        jitter = 0.5_wp
        if (particles%distribution == dist_random) then
            do a = 1, dim
                jitter(a) = uniform01(particles%seed, p, a)
            end do
        end if
        x = 0.0_wp
        do a = 1, dim
            x(a) = domain%origin(a) + (real(s(a), wp) + jitter(a))*h
        end do
    end function particle_position

    !> Reproducible uniform number in (0.05, 0.95) from (seed, particle, axis): splitmix64 hash.
    !>
    !> Independent of loop order and thread count; the margin keeps a particle off the
    !> faces of its sub-cell.
    pure real(wp) function uniform01(seed, p, axis)
        integer, intent(in) :: seed
            !! user seed
        integer, intent(in) :: p
            !! particle index
        integer, intent(in) :: axis
            !! coordinate axis

        integer(i8) :: z

        z = int(seed, i8)*1000003_i8 + int(p, i8)*3_i8 + int(axis, i8)
        z = z + (-7046029254386353131_i8)
        z = ieor(z, shiftr(z, 30))*(-4658895280553007687_i8)
        z = ieor(z, shiftr(z, 27))*(-7723592293110705685_i8)
        z = ieor(z, shiftr(z, 31))
        uniform01 = 0.05_wp + 0.9_wp*real(shiftr(z, 11), wp)/real(shiftl(1_i8, 53), wp)
    end function uniform01

end module mpm_case_sites
